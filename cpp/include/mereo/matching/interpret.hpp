// mereo/matching/interpret.hpp: from the lattice of hypotheses to the objects a frame is taken to
// hold (the judgement step), and the frame's result as one JSON line (the contract of DESIGN.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model.hpp"
#include "mereo/matching/match.hpp"

namespace mereo::matching {

/// One object hypothesis of the result: a concept with the segments of its present parts.
struct RecognizedObject {
  int id = 0;                      ///< index in the result's list
  std::string model;               ///< the concept's name ("mug")
  double score = 0.0;              ///< the hypothesis's score (eq. 5.5)
  double posterior = 0.0;          ///< P(concept | evidence)
  std::vector<std::pair<std::string, int>> parts;  ///< role -> segment index, present parts only
  bool accepted = false;           ///< part of the frame's interpretation
  std::vector<int> excludes;       ///< ids of the listed objects that share a segment with it
  int hypothesis = -1;             ///< index into Lattice::hypotheses
};

struct InterpretOptions {
  double min_score = 0.5;          ///< hypotheses below are not accepted
  double min_posterior = 0.5;      ///< nor below this posterior
  double list_score = 0.3;         ///< alternatives at or above this are listed (not accepted)

  /// The options of the report node.
  static const Fields<InterpretOptions>& fields();
};

inline const Fields<InterpretOptions>& InterpretOptions::fields() {
  using O = InterpretOptions;
  static const Fields<O> f = {
      field("min_score", &O::min_score, 0, 1, "hypotheses below this score are not accepted"),
      field("min_posterior", &O::min_posterior, 0, 1, "nor below this posterior"),
      field("list_score", &O::list_score, 0, 1, "alternatives at or above this are listed"),
  };
  return f;
}

/// The interpretation of a frame: hypotheses are accepted greedily, one per set of segments,
/// preferring those that explain more segments (a mug, body and handle, over a cup on the same
/// body), then the higher score, then the more specific concept (narrower attribute ranges: a
/// can over a jar), then the lattice's order; a hypothesis that shares a segment
/// with an accepted one is an alternative. Accepted objects come first (best first), then the
/// alternatives above options.list_score. Deterministic.
std::vector<RecognizedObject> interpret(const knowledge::KnowledgeBase& kb, const Lattice& lattice,
                                        const InterpretOptions& options = {});

/// The result of one frame as one JSON object (no newline), as in DESIGN.md's contract:
/// {"frame", "source", "objects": [{"id", "model", "score", "posterior", "accepted", "parts":
/// {role: {...}}, "excludes"}], "primitives": [...], "support_plane": {...} (when given),
/// "timing_ms": {...} (when given)}.
std::string result_json(const Frame& frame, const std::vector<Segment>& segments,
                        const std::vector<RecognizedObject>& objects,
                        const extension::SupportPlane* plane = nullptr,
                        const std::vector<std::pair<std::string, double>>& timing_ms = {});

/// One segment's parameters as a JSON object (class-specific fields, see DESIGN.md).
std::string segment_json(const Segment& s);

}  // namespace mereo::matching
