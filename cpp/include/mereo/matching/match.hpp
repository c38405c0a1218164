// mereo/matching/match.hpp: matching object models to data segments (the object layer), after
// Kasprzak et al.: a hypothesis assigns one segment of the right class to each part of a
// concept (optional parts may stay missing); its score is the product of the parts' attribute
// memberships, the constraints' values and the missing parts' factors (eq. 5.5); its judgement
// is the posterior of the concept's Bayesian net (bayes.hpp).
//
// Two searches return exactly the same N best hypotheses (score descending, ties broken by the
// assignment in lexicographic order):
//  - match_exhaustive: every assignment (eq. 5.6), the baseline;
//  - match: a branch-and-bound constraint optimisation: parts are assigned most-constrained
//    first, values best-scoring first; a branch is pruned when its upper bound (the partial
//    score times, for every unassigned part, its best value given the assigned parts: forward
//    checking) falls below the worst of the N kept or below min_score.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/knowledge/model.hpp"
#include "mereo/knowledge/predicates.hpp"

namespace mereo::matching {

struct Hypothesis {
  std::string concept_name;
  /// The concept's part set it was matched with (Concept::modalities: alternatives, such as a
  /// round or a conical bowl); "" for a concept without modalities.
  std::string modality;
  std::vector<int> assignment;  ///< per part of the modality (knowledge::select): segment index, -1 = missing
  double score = 0.0;           ///< eq. 5.5, in (0, 1]
  double posterior = 0.0;       ///< P(concept | evidence) from the concept's net
  /// Per part whose class is a concept (hierarchies): the sub-hypothesis assigned to it (its
  /// first segment is in `assignment`); empty when no part is a concept.
  std::vector<Hypothesis> children;
};

struct MatchOptions {
  int best = 10;                ///< N: hypotheses kept per concept
  double min_score = 1e-6;      ///< hypotheses below this score are dropped (and pruned)
  knowledge::Context context;   ///< the direction of "up" for above / on / tilt
  /// For parts whose class is a concept: the knowledge base to resolve it, and how many of its
  /// hypotheses (matched first, on the same segments) are candidates for the part.
  const knowledge::KnowledgeBase* kb = nullptr;
  int sub_best = 10;
  int depth = 0;                ///< nesting level (internal)

  /// The options of the Python functions match and recognize and of the match_models node.
  static const Fields<MatchOptions>& fields();
};

inline const Fields<MatchOptions>& MatchOptions::fields() {
  using O = MatchOptions;
  static const Fields<O> f = {
      field("best", &O::best, 1, 1000, "hypotheses kept per concept"),
      field("min_score", &O::min_score, 0, 1, "hypotheses below this score are dropped"),
  };
  return f;
}

struct MatchStats {
  std::size_t expanded = 0;     ///< search nodes visited (partial and complete assignments)
  std::size_t pruned = 0;       ///< branches cut by the bound, the threshold or forward checking
  std::size_t complete = 0;     ///< complete assignments scored
};

/// The membership product of the part's attributes for a segment (0 for a segment of another class).
double part_score(const knowledge::Concept& c, int part, const Segment& s, const knowledge::Context& ctx);

/// eq. 5.5 for a complete assignment (computed in a fixed order: parts, then constraints).
double hypothesis_score(const knowledge::Concept& c, const std::vector<int>& assignment,
                        const std::vector<Segment>& segments, const knowledge::Context& ctx);

/// The concept's posterior for a (partial: -2 = undecided) assignment.
double judge(const knowledge::Concept& c, const std::vector<int>& assignment,
             const std::vector<Segment>& segments, const knowledge::Context& ctx);

/// Every assignment of distinct segments to the parts (optional parts may be missing).
std::vector<Hypothesis> match_exhaustive(const knowledge::Concept& c, const std::vector<Segment>& segments,
                                         const MatchOptions& options = {}, MatchStats* stats = nullptr);

/// The branch-and-bound search: the same result as match_exhaustive, with far fewer nodes.
std::vector<Hypothesis> match(const knowledge::Concept& c, const std::vector<Segment>& segments,
                              const MatchOptions& options = {}, MatchStats* stats = nullptr);

/// The result of one frame: hypotheses of several concepts and the mutual-exclusion arcs
/// between any two that share a segment (the lattice of the method).
struct Lattice {
  std::vector<Hypothesis> hypotheses;          ///< by concept (in the order asked), best first
  std::vector<std::pair<int, int>> excludes;   ///< index pairs (i < j) into hypotheses
  /// Index pairs (i < j) of hypotheses of one concept and part set whose like parts (those both
  /// assign a segment, two or more) lie each within 1.25 times the larger one's extent (half its
  /// diagonal) of the other, centre to centre: one object seen in pieces (a chair whose seat and
  /// back were each found as two patches), not two (InterpretOptions::one_per_place). Two chairs
  /// side by side stand farther apart; a door beside a wall's strip, one part each, is never one.
  std::vector<std::pair<int, int>> same_place;
  MatchStats stats;
};

/// Matches every concept in `concepts` (resolved from `kb`, Fine detail, first modality; parts
/// whose class is a concept are matched to that concept's hypotheses first) in
/// parallel (oneTBB, one task per concept; the result does not depend on the thread count).
Lattice recognize(const knowledge::KnowledgeBase& kb, const std::vector<std::string>& concepts,
                  const std::vector<Segment>& segments, const MatchOptions& options = {});

}  // namespace mereo::matching
