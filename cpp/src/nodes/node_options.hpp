// The options of the nodes that take more than one library options struct: the struct's fields
// (nested, names unchanged) plus the node's own (the model file, the concepts...). Described
// once here; the node files build their option lists and values from these descriptions.
#pragma once

#include <string>
#include <vector>

#include "mereo/cognitive/odometry.hpp"
#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/options.hpp"
#include "mereo/matching/interpret.hpp"
#include "mereo/matching/match.hpp"

namespace mereo::nodes {

/// match_models: the concepts looked for, where the models come from, the search's options.
struct MatchModelsNodeOptions {
  std::vector<std::string> models{"mug", "cup", "jar", "can", "bottle", "plate", "bowl"};
  std::string file;  ///< a YAML model file; empty: the shipped models
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
  static const Fields<O> f = concat<O>(
      {list("models", &O::models, "comma-separated concepts to look for"),
       field("file", &O::file, "a YAML model file (empty: the shipped models)")},
      nested(&O::match, matching::MatchOptions::fields()));
  return f;
}

/// report: the model file, the interpretation's thresholds, the tracks' report threshold.
struct ReportNodeOptions {
  std::string file;
  matching::InterpretOptions interpret;
  double track_probability = 0.5;
  static const Fields<ReportNodeOptions>& fields();
};

inline const Fields<ReportNodeOptions>& ReportNodeOptions::fields() {
  using O = ReportNodeOptions;
  static const Fields<O> f = concat<O>(
      concat<O>({field("file", &O::file, "the model file of match_models (empty: the shipped models)")},
                nested(&O::interpret, matching::InterpretOptions::fields())),
      {field("track_probability", &O::track_probability, 0, 1, "with tracks: those at or above this are reported")});
  return f;
}

/// track_objects: the model file and the tracker's options.
struct TrackObjectsNodeOptions {
  std::string file;
  cognitive::TrackOptions track;
  static const Fields<TrackObjectsNodeOptions>& fields();
};

inline const Fields<TrackObjectsNodeOptions>& TrackObjectsNodeOptions::fields() {
  using O = TrackObjectsNodeOptions;
  static const Fields<O> f =
      concat<O>({field("file", &O::file, "the model file of match_models (empty: the shipped models)")},
                nested(&O::track, cognitive::TrackOptions::fields()));
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
