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

  bool valid() const { return fx > 0 && fy > 0; }
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
  /// Parses "fx,fy,cx,cy"; throws std::invalid_argument naming the text on a bad value.
  static Intrinsics parse(const std::string& text);
  /// The nominal Kinect / PrimeSense VGA intrinsics (525, 525, 319.5, 239.5).
  static Intrinsics kinect_vga() { return {}; }
};

/// A rigid transform from the camera frame to the world frame (x_world = pose * x_camera).
using Pose = Eigen::Isometry3d;

}  // namespace mereo
