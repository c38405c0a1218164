// The options of the nodes that take more than one library options struct, or options of their
// own: the struct's fields (nested, names unchanged) plus the node's own (the model file, the
// concepts...). Described once here; the node files build their option lists and values from
// these descriptions.
#pragma once

#include <string>
#include <vector>

#include "mereo/cognitive/odometry.hpp"
#include "mereo/core/options.hpp"
#include "mereo/matching/match.hpp"

namespace mereo::nodes {

/// models: the concepts looked for and where the models come from (the graph's one place of both).
struct ModelsNodeOptions {
  std::vector<std::string> models{"mug", "cup", "tapered_cup", "pitcher", "jar", "can", "bottle", "plate", "bowl"};
  std::string file;  ///< a YAML model file; empty: the shipped models
  static const Fields<ModelsNodeOptions>& fields();
};

inline const Fields<ModelsNodeOptions>& ModelsNodeOptions::fields() {
  using O = ModelsNodeOptions;
  static const Fields<O> f = {list("models", &O::models, "comma-separated concepts to look for"),
                              field("file", &O::file, "a YAML model file (empty: the shipped models)")};
  return f;
}

/// match_models: the search's options.
struct MatchModelsNodeOptions {
  /// The node drops weak hypotheses early (min_score 0.05); matching::match keeps all above 1e-6.
  matching::MatchOptions match = [] {
    matching::MatchOptions o;
    o.min_score = 0.05;
    return o;
  }();
  static const Fields<MatchModelsNodeOptions>& fields();
};

inline const Fields<MatchModelsNodeOptions>& MatchModelsNodeOptions::fields() {
  using O = MatchModelsNodeOptions;
  static const Fields<O> f = nested(&O::match, matching::MatchOptions::fields());
  return f;
}

/// report: the tracks' report threshold.
struct ReportNodeOptions {
  double track_probability = 0.5;
  static const Fields<ReportNodeOptions>& fields();
};

inline const Fields<ReportNodeOptions>& ReportNodeOptions::fields() {
  using O = ReportNodeOptions;
  static const Fields<O> f = {
      field("track_probability", &O::track_probability, 0, 1, "with tracks: those at or above this are reported")};
  return f;
}

/// odometry: whether to replace the frames' own poses, and the odometry's options.
struct OdometryNodeOptions {
  bool replace = false;
  cognitive::OdometryOptions odometry;
  static const Fields<OdometryNodeOptions>& fields();
};

inline const Fields<OdometryNodeOptions>& OdometryNodeOptions::fields() {
  using O = OdometryNodeOptions;
  static const Fields<O> f = concat<O>({field("replace", &O::replace, "estimate even where the frame has a pose")},
                                       nested(&O::odometry, cognitive::OdometryOptions::fields()));
  return f;
}

}  // namespace mereo::nodes
