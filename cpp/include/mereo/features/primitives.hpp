// mereo/features/primitives.hpp: RANSAC detection of planes, cylinders, tori and spheres in an
// organized frame (the feature layer).
//
// The method follows Schnabel, Wahl and Klein, "Efficient RANSAC for Point-Cloud Shape
// Detection", Computer Graphics Forum 26(2), 2007, adapted to organized frames:
//  - minimal sets that use the normals (each class's from_sample: plane 1 point, sphere 2,
//    cylinder 2, torus 4);
//  - sampling localized in image neighbourhoods (the organized frame's stand-in for the
//    paper's octree cells): a seed pixel, the others within a window whose metric size is
//    options.sample_radius at the seed's depth;
//  - scoring by point distance (epsilon) and normal deviation (alpha) over the connected
//    component of compatible pixels that contains the seed (the paper's largest connected
//    component, computed by a flood fill in the image on a grid of step score_step);
//  - the best candidates of an iteration that do not overlap a better one are refined by
//    least squares (Levenberg-Marquardt on the geometric distance), their full-resolution
//    component is recomputed, their pixels are removed, and the loop repeats until an
//    iteration finds nothing worth keeping.
// Candidates are drawn in parallel (oneTBB) from per-task generators seeded with
// (options.seed, iteration, task), so the result depends on the seed only, never on the
// number of threads.
//
// Model-driven search (the top-down rule of the method): find_primitive() looks for one class
// within a SearchRegion (pixel mask, ball near another segment, radius range) with
// thresholds suited to small parts, e.g. a mug's handle (a torus of tube radius 4-8 mm)
// next to its body.
//
// Units: metres, camera frame (x right, y down, z forward); angles in degrees in options.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/features/handle.hpp"

namespace mereo::features {

/// Options of detect_primitives / find_primitive. Defaults suit a Kinect-type VGA frame of a
/// table top at 0.5-2 m.
struct DetectOptions {
  std::uint64_t seed = 0;            ///< the only source of randomness
  /// Which classes to look for (those of the shape table with a minimal set; others are ignored).
  std::vector<PrimitiveClass> classes{PrimitiveClass::of<shapes::Plane>(), PrimitiveClass::of<shapes::Cylinder>(),
                                      PrimitiveClass::of<shapes::Torus>(), PrimitiveClass::of<shapes::Sphere>()};
  double epsilon = 0.006;            ///< max point-to-surface distance of an inlier, metres,
                                     ///< at 1 m; grows with depth like Kinect noise (see
                                     ///< epsilon_growth)
  double epsilon_growth = 0.5;       ///< epsilon(z) = epsilon * (1 + growth * (z^2 - 1)), z>=0.5
  double normal_deviation_deg = 25;  ///< max angle between the point's and the surface's normal
  int min_support = 250;             ///< min inlier pixels of a plane, cylinder or sphere
  int min_support_torus = 80;        ///< min inlier pixels of a torus
  double sample_radius = 0.05;       ///< metric radius of the sampling neighbourhood, metres
  int score_step = 2;                ///< grid step (pixels) of candidate scoring
  int candidates_per_iteration = 384;///< seeds drawn per iteration (each gives one candidate
                                     ///< per class)
  int max_iterations = 60;           ///< upper bound on detect-refine-remove rounds
  int max_primitives = 64;
  double min_radius = 0.01;          ///< cylinder and sphere radius range, metres
  double max_radius = 0.35;
  double min_minor_radius = 0.003;   ///< torus tube radius range, metres
  double max_minor_radius = 0.02;
  double max_major_radius = 0.08;    ///< torus ring radius upper bound, metres
  /// The model-driven search for handles next to the cylinders found bottom-up (tori then are
  /// looked for there only, when Torus is in `classes`), and every constant of what a handle is.
  HandleOptions handle;
  /// Optional region of interest: pixels with a non-zero value are used (same size as the
  /// cloud); empty = all pixels.
  Image<std::uint8_t, 1> roi;
  /// The support plane (unit normal up, d: normal.dot(x) + d is the height above it; camera
  /// frame), when known: upright cylinders (bodies standing on the support) are then also looked
  /// for without normals, after the bottom-up search, in the pixels it left (noisy depth, e.g.
  /// active stereo beyond a metre, turns normals too far for it). Zero = unknown.
  Eigen::Vector4d support = Eigen::Vector4d::Zero();
  /// Look for upright bodies without normals where `up` is known (false: the bottom-up search only).
  bool upright_bodies = true;
  /// Focal length in pixels for the sampling window; 0 = fitted to the cloud.
  double focal_px = 0.0;
  /// Cylinders and spheres are fitted along the rays (refit's along_rays): the maximum-likelihood
  /// fit for sensors whose noise lies along the rays (structured light, time of flight), and
  /// unbiased there, where the geometric fit shrinks the radius (by ~0.6 mm at 1.3 m). false: by
  /// geometric distance, for clouds whose noise lies across the surface as much as along the
  /// ray (the PCL stereo mug's: see bench_primitives).
  bool fit_along_rays = true;
  /// Optional: the frame's unfiltered points (same grid as the cloud; camera frame). Cylinders
  /// and spheres are then measured on them: their least-squares fits run on these points of
  /// their inlier pixels. Smoothing depth flattens a curved
  /// surface: after the 3x3 bilateral filter a 4 cm cylinder fits ~0.4 mm too wide at 1.2 m.
  /// Empty = the cloud's points.
  Cloud unfiltered;

  /// The options of the detect_primitives node and Python function (not roi, unfiltered and
  /// the internal tuning above: they come from ports or stay at their defaults).
  static const Fields<DetectOptions>& fields();
};

inline const Fields<DetectOptions>& DetectOptions::fields() {
  using O = DetectOptions;
  static const Fields<O> f = concat<O>({
      field("seed", &O::seed, 0, 1e15, "the only source of randomness"),
      list("classes", &O::classes, [](PrimitiveClass c) { return to_string(c); }, primitive_class,
           "classes to look for"),
      field("epsilon", &O::epsilon, 1e-4, 0.1, "inlier distance at 1 m, metres"),
      field("normal_deviation_deg", &O::normal_deviation_deg, 1, 90, "inlier normal deviation"),
      field("min_support", &O::min_support, 10, 1e7, "fewest pixels of a segment"),
      field("min_support_torus", &O::min_support_torus, 10, 1e7, "fewest pixels of a torus"),
      field("max_primitives", &O::max_primitives, 1, 10000, "at most this many segments"),
      field("upright_bodies", &O::upright_bodies,
            "given the support plane, also look for upright cylinders without normals (noisy depth)"),
      field("fit_along_rays", &O::fit_along_rays,
            "fit cylinders and spheres along the rays (depth noise along them); false: by geometric distance"),
  }, nested(&O::handle, HandleOptions::fields()));
  return f;
}

/// Where find_primitive looks. All given constraints apply together.
struct SearchRegion {
  /// Pixels with a non-zero value may be inliers (same size as the cloud); empty = all.
  Image<std::uint8_t, 1> mask;
  /// A ball: points within `ball_radius` of `ball_center` (metres, camera frame); radius 0 =
  /// no ball.
  Eigen::Vector3d ball_center = Eigen::Vector3d::Zero();
  double ball_radius = 0.0;
  /// Radius range of the wanted primitive (cylinder/sphere radius, torus major radius);
  /// 0 = the options' range.
  double min_radius = 0.0;
  double max_radius = 0.0;
  /// Torus tube radius range; 0 = the options' range.
  double min_minor_radius = 0.0;
  double max_minor_radius = 0.0;
  /// Pixels already taken (e.g. the inliers of other segments) are excluded; these segments'
  /// pixels are removed from the search.
  std::vector<const Segment*> exclude;
  /// A cylinder (a body) the wanted torus (a handle) is attached to: its ring plane then holds
  /// the body's axis direction, which find_primitive uses to draw handle hypotheses (a circle in
  /// that plane through three tube centres) instead of the generic four-point torus.
  std::optional<Segment> attached_to;
};

/// A ball region around `segment`: its centre point with radius extent + margin (a handle
/// next to a body: the body's radius and half height plus `margin` metres); for a cylinder the
/// region is also `attached_to` it.
SearchRegion region_near(const Segment& segment, double margin = 0.06);

/// Finds planes, cylinders, tori and spheres in an organized cloud with per-pixel normals
/// (unit, towards the camera, NaN where undefined), largest first. Each segment carries its
/// class, parameters (see Segment), inlier pixels, visible extent (cylinder height), RMS
/// residual, and the mean colour and hue of its pixels when `color` is given.
/// Throws InputError when the images disagree in size or an option is out of range.
std::vector<Segment> detect_primitives(const Cloud& cloud, const NormalMap& normals,
                                       const DetectOptions& options = {},
                                       const ColorImage* color = nullptr);

/// Model-driven search: the best primitives of class `cls` inside `region` (at most
/// `max_count`, best first; empty when none has the support). Uses small-part thresholds
/// (the options' min_support_torus for tori, min_support / 4 otherwise) and samples only
/// inside the region.
std::vector<Segment> find_primitive(const Cloud& cloud, const NormalMap& normals,
                                    PrimitiveClass cls, const SearchRegion& region,
                                    const DetectOptions& options = {},
                                    const ColorImage* color = nullptr, int max_count = 1);

/// Distance (metres, >= 0) of point `x` to the unbounded surface of segment `s`.
double surface_distance(const Segment& s, const Eigen::Vector3d& x);

/// Least-squares refit of a segment's parameters to points (Levenberg-Marquardt, starting from
/// `s`); returns the refined segment (pixels unchanged). It minimises the geometric distance,
/// or with `along_rays` (camera-frame points of a depth image; cylinders and spheres) each
/// point's range error along its pixel's ray: a depth sensor's noise lies along the ray, and
/// the geometric fit is then biased (a cylinder's radius shrinks by ~0.1 mm at 0.7 m, ~0.7 mm at
/// 1.3 m on the Kinect-like noise). The detector's own fits are along the rays.
Segment refit(const Segment& s, const std::vector<Eigen::Vector3d>& points, bool along_rays = false);

}  // namespace mereo::features
