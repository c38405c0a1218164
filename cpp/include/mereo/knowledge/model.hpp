// mereo/knowledge/model.hpp: object models (the TBox of Kasprzak et al.): concepts with parts,
// attributes, constraints, modalities, specialization, part hierarchies and levels of detail.
//
// A concept (mug) has parts with unique roles (body, handle), each of a class that is either a
// primitive (plane, cylinder, torus, sphere, line, arc) or another concept (hierarchies).
// Attributes restrict one part's data (body.radius within 3-5.5 cm, as a fuzzy membership);
// constraints relate two or more parts by fuzzy predicates in [0, 1] (near, intersects, ...;
// see predicates.hpp). A concept may specialize another (`parent`): it inherits the parent's
// parts, attributes and constraints, may add its own and may narrow inherited ranges.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/segment.hpp"
#include "mereo/knowledge/fuzzy.hpp"

namespace mereo::knowledge {

/// Level of detail of a part: coarse parts generate hypotheses fast, fine parts verify them.
enum class Detail { Coarse, Fine };
const char* to_string(Detail d);

struct Part {
  std::string role;                ///< unique within the concept ("body", "handle")
  std::string cls;                 ///< a primitive name ("cylinder") or a concept name
  bool optional = false;           ///< obligatory parts must be assigned in every hypothesis
  Detail detail = Detail::Coarse;
  double missing_score = 0.5;      ///< eq. 5.5 factor of an optional part left unassigned
  /// Interchangeable parts (a chair's four legs) share a group name: a hypothesis assigns their
  /// segments in increasing order (missing ones last), so that permutations of the same segments
  /// are one hypothesis, not 4! of them. Parts of a group have the same class.
  std::string group;
  std::string origin;              ///< "file:line:column" where it was defined (messages)
};

/// A fuzzy range over one attribute of one part's data, e.g. body.radius in [0.03, 0.055] m.
/// Attribute names: see attribute_names() in predicates.hpp (radius, height, minor_radius,
/// aspect, tilt_deg, inliers, residual, hue, ...). Lengths in metres, angles in degrees.
struct Attribute {
  std::string part;
  std::string name;
  Membership range;
  std::string origin;
};

struct Context;
struct Constraint;

/// A user-defined predicate (C++ or Python, for experiments): the parts' data in the order of
/// Constraint::parts, returns a value in [0, 1].
using PredicateFn = std::function<double(const std::vector<const Segment*>& parts,
                                         const Constraint& constraint, const Context& context)>;

/// A fuzzy relation between two or more parts. Built-in predicates (predicates.hpp) are named;
/// a custom one sets `custom` (its `predicate` is then only a name for messages).
struct Constraint {
  std::string predicate;                   ///< "near", "intersects", "parallel", ...
  std::vector<std::string> parts;          ///< roles, in the predicate's argument order
  std::map<std::string, double> params;    ///< e.g. {"max": 0.01} (metres, degrees)
  PredicateFn custom;
  std::string origin;

  double param(const std::string& name, double fallback) const;
};

/// An alternative part set (e.g. surface-based vs edge-based mug).
struct Modality {
  std::string name;
  std::vector<std::string> parts;
};

/// Conditional probabilities of a concept's Bayesian net (bayes.hpp), each as
/// {P(x | concept), P(x | not concept)}. The defaults derive the net from the model.
struct BayesParams {
  double prior = 0.5;                                   ///< P(concept)
  std::pair<double, double> present_obligatory{0.95, 0.3};
  std::pair<double, double> present_optional{0.6, 0.3};
  std::pair<double, double> quality{0.9, 0.25};         ///< P(part data fits | present)
  std::pair<double, double> satisfied{0.9, 0.15};       ///< P(constraint holds | its parts present)
  /// Per-node overrides: "present:handle", "quality:body", "satisfied:0" (constraint index).
  std::map<std::string, std::pair<double, double>> node;
};

struct Concept {
  std::string name;
  std::string parent;              ///< specialization link ("" for none)
  std::string description;
  std::vector<Part> parts;
  std::vector<Attribute> attributes;
  std::vector<Constraint> constraints;
  std::vector<Modality> modalities;  ///< empty: one modality with every part
  BayesParams bayes;
  std::string origin;

  const Part* part(const std::string& role) const;
  int part_index(const std::string& role) const;  ///< -1 if none
};

/// True for "plane", "cylinder", "torus", "sphere", "line", "arc".
bool is_primitive(const std::string& cls);

/// A set of concepts with their specialization links.
class KnowledgeBase {
 public:
  /// Adds (or replaces) a concept. Consistency is checked by validate() / resolve().
  void add(Concept c);
  bool has(const std::string& name) const;
  const Concept& get(const std::string& name) const;  ///< as defined (not flattened)
  std::vector<std::string> names() const;

  /// The concept with everything it inherits: parent parts first, then its own; an attribute
  /// or constraint given again for the same part(s) and predicate replaces the inherited one,
  /// and a replaced attribute range must lie within the inherited one (narrowing only).
  /// Throws InputError naming the origin (file:line) and field on unknown parents, cycles,
  /// unknown classes or roles, duplicate roles, unknown predicates or attributes, widening.
  Concept resolve(const std::string& name) const;

  /// resolve()s every concept (throws on the first error).
  void validate() const;

  /// True if `cls` is `ancestor` or specializes it (a mug is a container).
  bool is_a(const std::string& cls, const std::string& ancestor) const;
  /// The concepts `cls` specializes, nearest first (coffee_table: {"table"}); empty for a root
  /// concept or an unknown name.
  std::vector<std::string> ancestors(const std::string& cls) const;

 private:
  std::map<std::string, Concept> concepts_;
};

/// The part set of one modality (by name; "" = the first, or all parts when there are none)
/// at one level of detail (Coarse keeps coarse parts only, Fine keeps all), with the
/// attributes and constraints that involve only the kept parts.
Concept select(const Concept& resolved, const std::string& modality = "",
               Detail detail = Detail::Fine);

}  // namespace mereo::knowledge
