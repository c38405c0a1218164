// mereo/features/patches.hpp: bounded planar patches (shapes/patch.hpp) of an organized cloud, the
// primitives of a room (floors, walls, table tops, seats, backs, doors): an organized multi-plane
// segmentation that grows regions over a pixel grid, each held to the plane of what it has
// gathered so far (a curved sofa or a ball does not grow into one long patch), apart at depth
// jumps, and describes each as the rectangle that holds it in its plane. With gravity known,
// level surfaces are grown first, held to up.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::features {

struct PatchOptions {
  int step = 2;                 ///< the grid's step, pixels (its cells are grown; every pixel is labelled)
  double epsilon = 0.012;       ///< a point's distance to the patch's plane at 1 m, metres (grows with z^2)
  double max_angle_deg = 20.0;  ///< between a point's normal and the patch's plane's
  double depth_jump = 0.04;     ///< a depth step between grid neighbours (times the depth) that parts patches
  double min_area = 0.02;       ///< smaller patches are none, square metres
  int min_pixels = 300;         ///< ... and those with fewer pixels
  /// With gravity known, a patch within this of upright (a wall, a door, a chair's back) has its
  /// u_axis horizontal and size_v its height; others (and all without gravity) their main direction.
  double upright_deg = 30.0;
  /// With gravity known and level_deg > 0, level patches are grown first about the plane normal
  /// to up, of cells whose normals lean no more than this from up (seeds: half of it); the others
  /// then as above. A seat or a table top seen at a grazing angle has the worst normals of a frame
  /// but well measured heights: grown on its plane it is found whole, its sizes within 2-3 cm.
  /// Level pieces at one height whose points come within 5 cm are then one patch (a top seen at a
  /// grazing angle, parted by its rows' depth steps). 0: off.
  double level_deg = 30.0;
  /// A level region narrower than this (its cells' thinner horizontal spread, as the side of a
  /// rectangle) is a band across an upright surface (a back, a wall, blinds' slats), not a level
  /// patch: its cells are left to the upright growth. Metres.
  double level_min_width = 0.1;
  /// With a colour image, growth does not cross between neighbouring cells whose mean colours
  /// differ by more than this (RGB in [0, 1], Euclidean): a door in the plane of its wall (rendered
  /// rooms 9100-9119: doors 5/20 -> 6/20; the real room frames: unchanged); nor does upright
  /// growth enter a cell with a step this large between neighbouring pixels (a door's edge, where
  /// the cells' means blend door, wall and the gap between them). 0: off.
  double colour_edge = 0.15;
  /// Patches whose points are mostly farther than this (metres, along the optical axis) are
  /// none: beyond it a depth camera's surfaces break into pieces whose sizes mean little.
  double max_depth = 6.0;
  /// The rim that the normals' window leaves at a patch's edges (its normals bent by what lies
  /// beyond) is given back to upright patches (to all without gravity), this many pixels out: a
  /// pixel beside one joins the one whose plane lies nearest to it, within half the growth's
  /// tolerance, without a depth jump. A door's or a cabinet's sides come out 5-6 cm short each at
  /// 4-5 m without it. Level patches keep their sizes: given their rims, the pieces of a cluttered
  /// desk grew into tables of their own (TUM). 0: off.
  int rim = 8;

  static const Fields<PatchOptions>& fields();
};

inline const Fields<PatchOptions>& PatchOptions::fields() {
  using O = PatchOptions;
  static const Fields<O> f = {
      field("step", &O::step, 1, 16, "grid step of the region growing, pixels"),
      field("epsilon", &O::epsilon, 1e-4, 0.5, "a point's distance to its patch's plane at 1 m, metres"),
      field("max_angle_deg", &O::max_angle_deg, 1, 90, "a point's normal to its patch's, degrees"),
      field("depth_jump", &O::depth_jump, 0.001, 1, "a depth step between neighbours (times the depth) that parts patches"),
      field("min_area", &O::min_area, 0, 1e4, "least area of a patch, square metres"),
      field("min_pixels", &O::min_pixels, 1, 1e7, "fewest pixels of a patch"),
      field("upright_deg", &O::upright_deg, 0, 90, "with gravity: patches this close to upright get a horizontal u_axis"),
      field("max_depth", &O::max_depth, 0.1, 100, "patches whose median depth is beyond this are none, metres"),
      field("rim", &O::rim, 0, 64, "pixels beside a patch, this far out, join the nearest plane (the normals' rim); 0: off"),
      field("colour_edge", &O::colour_edge, 0, 2, "with colour: growth does not cross a colour step larger than this (0: off)"),
      field("level_deg", &O::level_deg, 0, 90, "with gravity: level patches take cells whose normals lean at most this from up"),
      field("level_min_width", &O::level_min_width, 0, 10, "level regions narrower than this are bands across upright surfaces, metres"),
  };
  return f;
}

/// The planar patches of an organized cloud with normals (unit, NaN where undefined): segments of
/// class patch, largest first, each with its pixels (every pixel within epsilon of its plane in
/// the cells it grew over), inlier count, RMS residual and mean colour (with `color`). `up` (camera
/// frame, against gravity; optional) orients upright patches' rectangles. Throws InputError when
/// the sizes differ. Deterministic.
std::vector<Segment> planar_patches(const Cloud& cloud, const NormalMap& normals, const PatchOptions& options = {},
                                    const Eigen::Vector3d* up = nullptr, const ColorImage* color = nullptr);

}  // namespace mereo::features
