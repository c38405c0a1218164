// mereo/extension/support_plane.hpp: the dominant horizontal plane under the objects (the table),
// its polygon, the region of interest above it, and a world frame with z up from it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/camera.hpp"
#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"

namespace mereo::extension {

/// 8-bit mask: non-zero = selected.
using Mask = Image<std::uint8_t, 1>;

struct SupportPlaneOptions {
  std::uint64_t seed = 0;              ///< the only source of randomness (plane hypotheses)
  /// Camera-frame direction against gravity, when known (e.g. from a pose); the plane's
  /// normal must lie within max_tilt_deg of it. Unset: -y (the camera's up), with the wider
  /// tolerance max_tilt_deg_unknown, for a camera looking down at a table.
  std::optional<Eigen::Vector3d> up;
  double max_tilt_deg = 15.0;
  double max_tilt_deg_unknown = 75.0;
  /// Inlier tolerance at 1 m (metres); it grows with z^2 like Kinect depth noise.
  double epsilon = 0.008;
  double normal_deviation_deg = 20.0;  ///< max angle between an inlier's normal and the plane's
  int hypotheses = 200;                ///< plane hypotheses (a seed point and its normal)
  int step = 6;                        ///< pixel grid step for scoring hypotheses
  int min_inliers = 2000;              ///< fewest full-resolution inliers of a support plane
  /// Distinct planes (the best hypotheses after non-maximum suppression) refitted and compared.
  /// Each is weighed by its pixels and the pixels standing on it, four times near the centre of
  /// the view; of parallel planes, the highest whose weight is at least min_share of the heaviest
  /// and whose polygon has at least min_area (square metres; not the top of a box) is the
  /// support (a desk over a larger carpet, a coffee table over the floor).
  int candidates = 4;
  double min_share = 0.3;
  double min_area = 0.05;
  /// Of parallel planes a step apart, the support is the highest (a table: the tabletop graph) or
  /// the lowest (a room's floor under its tables and seats: the room graph) that qualifies.
  enum class Prefer { Highest, Lowest } prefer = Prefer::Highest;
  /// The region of interest: points between min_height and max_height above the plane whose
  /// projection falls inside the polygon shrunk by `margin` (metres). min_height is its value
  /// at 1 m and grows with z^2 beyond (depth noise), so that the table's own noisy points stay out.
  double min_height = 0.006;
  double max_height = 0.40;
  double margin = 0.0;
  /// Where the plane's region runs into the image's border the table goes on out of view: the
  /// region of interest reaches this far (metres) beyond such an edge of the polygon, so that an
  /// object standing near the camera, whose foot is out of view, stays in it.
  double beyond_border = 0.25;

  /// The options of the support_plane node and the find_support_plane Python function (`up`
  /// comes from the frame's pose, or is a separate argument).
  static const Fields<SupportPlaneOptions>& fields();
};

inline const Fields<SupportPlaneOptions>& SupportPlaneOptions::fields() {
  using O = SupportPlaneOptions;
  static const Fields<O> f = {
      field("seed", &O::seed, 0, 1e15, "random seed of the plane hypotheses"),
      field("epsilon", &O::epsilon, 1e-4, 0.1, "inlier distance at 1 m, metres"),
      field("min_inliers", &O::min_inliers, 10, 1e7, "fewest points of the plane"),
      field("candidates", &O::candidates, 1, 50, "distinct planes compared"),
      field("min_share", &O::min_share, 0, 1, "a higher plane's least share of the heaviest plane's weight"),
      field("min_area", &O::min_area, 0, 100, "a higher plane's least area, square metres"),
      choice("prefer", &O::prefer, {{"highest", O::Prefer::Highest}, {"lowest", O::Prefer::Lowest}},
             "of parallel planes a step apart: the highest (a table) or the lowest (a room's floor)"),
      field("min_height", &O::min_height, 0, 1, "ROI: lowest height above the plane, metres"),
      field("max_height", &O::max_height, 0.01, 5, "ROI: highest height above the plane, metres"),
      field("margin", &O::margin, -1, 1, "ROI: polygon shrunk by this, metres"),
      field("beyond_border", &O::beyond_border, 0, 5, "ROI: reach beyond the polygon's edges on the image's border, metres"),
  };
  return f;
}

/// The support plane of one frame. Geometry in metres, camera frame, unless it says world.
struct SupportPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, towards the camera (up)
  double d = 0.0;                     ///< normal.dot(x) + d = 0 on the plane; > 0 above it
  std::vector<Eigen::Vector3d> polygon;  ///< convex hull of the plane's region, on the plane
  /// Per polygon vertex, the image borders its pixel lies on (bits: kLeft, kRight, kTop,
  /// kBottom). An edge between two vertices on the same border is the view's edge, not the
  /// table's: the plane goes on beyond it.
  std::vector<std::uint8_t> borders;
  enum Border : std::uint8_t { kLeft = 1, kRight = 2, kTop = 4, kBottom = 8 };
  Mask inliers;                       ///< pixels of the plane (its largest connected region)
  Mask roi;                           ///< pixels above the plane, inside the polygon
  std::size_t inlier_count = 0;
  double rms = 0.0;                   ///< RMS distance of the inliers to the plane, metres
  /// The depth's noise, measured on the plane: the standard deviation of a point's error along
  /// its line of sight at 1 m (metres), taken to grow with the square of the depth (structured
  /// light and stereo alike), from the spread of its farther points (support_plane.cpp: depth_noise).
  /// 0 = too few points to tell.
  double noise = 0.0;
  /// World frame with z up from the table: origin = the inliers' centroid projected on the
  /// plane, z = normal, x = the camera's x projected on the plane. x_world = world_from_camera * x.
  Pose world_from_camera = Pose::Identity();

  /// Signed height of x above the plane, metres.
  double height(const Eigen::Vector3d& x) const { return normal.dot(x) + d; }
};

/// Finds the support plane in an organized cloud with normals (unit, towards the camera, NaN
/// where undefined): RANSAC over one-point-and-normal hypotheses restricted to near-horizontal
/// normals, scored on a pixel grid by the points within a depth-dependent distance and normal
/// deviation; the best hypotheses of distinct planes are each refitted by least squares (PCA) to
/// their connected regions, twice, and weighed by what the camera looks at (see `candidates`):
/// the desk with the objects in the middle of the view over a larger carpet, not the top of a box
/// on it. Throws InputError when the sizes differ or no plane has min_inliers (an empty or
/// all-NaN frame, a view without a table).
SupportPlane find_support_plane(const Cloud& cloud, const NormalMap& normals,
                                const SupportPlaneOptions& options = {});

/// The region of interest of `plane` in `cloud` (what find_support_plane puts in `roi`): up to
/// `beyond_border` metres past the polygon's edges on the image's border.
Mask region_above(const Cloud& cloud, const SupportPlane& plane, double min_height,
                  double max_height, double margin = 0.0, double beyond_border = 0.0);

}  // namespace mereo::extension
