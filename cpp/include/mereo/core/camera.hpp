// mereo/core/camera.hpp: pinhole intrinsics and the camera pose.
#pragma once

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
