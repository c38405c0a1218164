// mereo/core/segment.hpp: a detected primitive (the feature layer's output, the object layer's
// data instance). Coordinates in metres, camera frame, unless a field says world.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mereo {

enum class PrimitiveClass { Plane, Cylinder, Torus, Sphere, Line, Arc };

/// "plane", "cylinder", "torus", "sphere", "line", "arc" (the names of the JSON output).
const char* to_string(PrimitiveClass c);
/// The class of a name; throws std::invalid_argument listing the known names.
PrimitiveClass primitive_class(const std::string& name);

/// One segment: a primitive's parameters, its inlier pixels and attributes.
///  - plane:    `axis` = unit normal (towards the camera), `d` with axis.dot(x) + d = 0,
///              `point` = centroid of the inliers;
///  - cylinder: `point` on the axis at the middle of the visible extent, unit `axis`, `radius`,
///              `height` = visible extent along the axis;
///  - torus:    `point` = centre, `axis` = unit normal of the ring plane, `radius` = major radius,
///              `minor_radius`;
///  - sphere:   `point` = centre, `radius`.
struct Segment {
  int id = -1;
  PrimitiveClass cls = PrimitiveClass::Plane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  double radius = 0.0;
  double minor_radius = 0.0;
  double height = 0.0;
  std::size_t inliers = 0;          ///< number of inlier pixels
  double residual = 0.0;            ///< RMS point-to-surface distance of the inliers, metres
  Eigen::Vector3f mean_color = Eigen::Vector3f::Zero();  ///< RGB in [0, 1]
  double hue = 0.0;                 ///< degrees [0, 360) of mean_color
  /// Cylinder, sphere, torus: seen from inside (its pixels' normals point towards the axis or
  /// centre: a mug's inner wall, a bowl's inside), not from outside.
  bool inward = false;
  std::vector<int> pixels;          ///< inlier pixel indices v * width + u
};

}  // namespace mereo
