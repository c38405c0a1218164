// mereo/core/camera.hpp: pinhole intrinsics and the camera pose.
#pragma once

#include <cmath>
#include <string>

#include <Eigen/Geometry>

namespace mereo {

/// Pinhole intrinsics in pixels: u = fx * x / z + cx, v = fy * y / z + cy
/// (x right, y down, z forward, metres).
struct Intrinsics {
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;

  /// The largest focal length taken, in pixels (a 0.0006 degree pixel: no camera mereo serves).
  static constexpr double kMaxFocal = 1e5;
  /// Focal lengths finite, positive and at most kMaxFocal; principal point finite.
  bool valid() const { return problem().empty(); }
  /// What is wrong with these intrinsics for a cols x rows image ("" when nothing; with cols and
  /// rows 0 the principal point is only checked to be finite): focal lengths as valid() says, the
  /// principal point inside the image.
  std::string problem(int cols = 0, int rows = 0) const;
  /// The pixel (u, v) a camera-frame point projects to, rounded; `x.z()` must be positive.
  Eigen::Vector2i pixel(const Eigen::Vector3d& x) const {
    return {int(std::lround(fx * x.x() / x.z() + cx)), int(std::lround(fy * x.y() / x.z() + cy))};
  }
  /// The camera-frame point seen at pixel (u, v) with depth z.
  Eigen::Vector3d point(double u, double v, double z) const { return {(u - cx) * z / fx, (v - cy) * z / fy, z}; }
  bool operator==(const Intrinsics& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy;
  }
  /// "fx,fy,cx,cy", the form the command line takes.
  std::string to_string() const;
  /// Parses "fx,fy,cx,cy"; throws InputError naming the text on a bad value.
  static Intrinsics parse(const std::string& text);
  /// The nominal Kinect / PrimeSense VGA intrinsics (525, 525, 319.5, 239.5).
  static Intrinsics kinect_vga() { return {}; }
};

/// A rigid transform from the camera frame to the world frame (x_world = pose * x_camera).
using Pose = Eigen::Isometry3d;

/// Whether a 4x4 matrix is a rigid transform: finite, a rotation (orthonormal within 1e-3, no
/// reflection) and a translation, last row 0 0 0 1.
inline bool is_rigid(const Eigen::Matrix4d& M) {
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  return M.allFinite() && (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() <= 1e-3 && R.determinant() > 0 &&
         M.row(3) == Eigen::RowVector4d(0, 0, 0, 1);
}

/// A depth camera beside the colour camera (raw Kinect streams, NYU's raw frames, 7-Scenes):
/// its intrinsics and the rigid transform from its frame to the colour camera's (x_color =
/// to_color * x_depth, metres). A frame read with one has its depth registered to the colour
/// camera (signal::register_depth) before colour meets depth.
struct DepthCamera {
  Intrinsics intrinsics;
  Pose to_color = Pose::Identity();
};

}  // namespace mereo
