// mereo/features/legs.hpp: the legs under a room's level patches (a table's top, a chair's seat),
// the furniture models' fine level of detail (graphs/models/room.yaml: a dining chair stands on
// legs, an office chair on a column). A leg is a thin upright support between the floor and the
// patch: the points under the patch's rectangle (grown by a margin), between a little above the
// floor and a little below the patch, binned on a horizontal grid; each 8-connected group of
// occupied cells that is narrow, spans most of that height and reaches up to the patch is one
// (unless it rises on past the patch alone: a table's leg beside a seat), a segment of class cylinder (shapes/cylinder.hpp: axis up, `point` at the middle of the span seen,
// `radius` half the group's width, `height` the span seen).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::shapes {
struct Patch;
}

namespace mereo::features {

struct LegOptions {
  double min_top = 0.25;      ///< the level patches looked under: their height above the floor, metres
  double max_top = 1.2;
  double max_tilt_deg = 12;   ///< ... and their normal's angle to up
  double margin = 0.06;       ///< how far beyond the patch's rectangle a leg may stand, metres
  double cell = 0.03;         ///< the horizontal grid's cell, metres
  /// Points lower than this are not looked at: an office chair's five-star base and the floor's
  /// depth noise would join the legs at their feet. Metres.
  double floor_clear = 0.1;
  /// Nor those within this of the patch's height: the top and its front face (a seat 3-7 cm thick,
  /// a table's apron), which would join its legs into one wide group. Metres.
  double top_clear = 0.1;
  /// A wider group is no leg (a chair's back under a table); depth noise widens a 3 cm leg seen
  /// at 3-4 m to 9-15 cm. Metres.
  double max_width = 0.18;
  /// A leg spans at least this share of the height between floor_clear and the patch (a leg half
  /// hidden behind another still does), and reaches up to within reach of the patch.
  double min_span = 0.5;
  double reach = 0.2;         ///< metres
  int min_points = 12;        ///< fewest points of a leg
  int step = 1;               ///< pixel step of the scan

  static const Fields<LegOptions>& fields();
};

inline const Fields<LegOptions>& LegOptions::fields() {
  using O = LegOptions;
  static const Fields<O> f = {
      field("min_top", &O::min_top, 0, 10, "lowest level patch looked under, metres above the floor"),
      field("max_top", &O::max_top, 0, 10, "highest level patch looked under, metres above the floor"),
      field("max_tilt_deg", &O::max_tilt_deg, 0, 90, "a level patch's normal to up, degrees"),
      field("margin", &O::margin, 0, 1, "how far beyond the patch's rectangle a leg may stand, metres"),
      field("cell", &O::cell, 0.005, 0.5, "the horizontal grid's cell, metres"),
      field("floor_clear", &O::floor_clear, 0, 1, "points lower than this above the floor are not looked at, metres"),
      field("top_clear", &O::top_clear, 0, 1, "nor those within this of the patch's height, metres"),
      field("max_width", &O::max_width, 0.01, 1, "widest leg, metres"),
      field("min_span", &O::min_span, 0, 1, "least share of the height under the patch a leg spans"),
      field("reach", &O::reach, 0, 1, "a leg's top lies within this of the patch, metres"),
      field("min_points", &O::min_points, 1, 1e6, "fewest points of a leg"),
      field("step", &O::step, 1, 16, "pixel step of the scan"),
  };
  return f;
}

/// The level patches among `segments` (class patch) that find_legs looks under, highest first.
std::vector<const shapes::Patch*> leg_tops(const std::vector<Segment>& segments, const Eigen::Vector3d& up,
                                           double floor_d, const LegOptions& options = {});
/// Whether a group of points under a patch `h` above the floor, `width` across and seen from `lo`
/// to `hi` above the floor, has a leg's shape: narrow, spanning most of the height under the
/// patch, reaching up to it.
bool leg_shaped(double width, double lo, double hi, double h, const LegOptions& options = {});

/// The legs under the level patches among `segments` (class patch; others are ignored): segments
/// of class cylinder, each with its pixels, under the highest patch first (a point is one leg's at
/// most). `up` is the floor's normal and `floor_d` its offset (up . x + floor_d is a point's height
/// above the floor), in the cloud's frame. Deterministic.
std::vector<Segment> find_legs(const Cloud& cloud, const std::vector<Segment>& segments, const Eigen::Vector3d& up,
                               double floor_d, const LegOptions& options = {});

}  // namespace mereo::features
