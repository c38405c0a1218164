// Registration of depth to the colour camera (see register.hpp).
#include "mereo/signal/register.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mereo/core/error.hpp"

namespace mereo::signal {

DepthImage register_depth(const DepthImage& depth, const DepthCamera& camera, const Intrinsics& color, int rows,
                          int cols) {
  if (rows <= 0 || cols <= 0) throw InputError("register_depth: the colour image is empty");
  if (depth.empty()) throw InputError("register_depth: the depth image is empty");
  if (const auto p = camera.intrinsics.problem(); !p.empty()) throw InputError("register_depth: the depth camera: " + p);
  if (const auto p = color.problem(); !p.empty()) throw InputError("register_depth: the colour camera: " + p);
  if (!is_rigid(camera.to_color.matrix()))
    throw InputError("register_depth: the depth-to-colour transform is not a rotation and a translation");
  const Eigen::Matrix3d R = camera.to_color.linear();
  // each depth pixel's point moved into the colour camera and projected to its nearest pixel,
  // the nearest point kept (a z-buffer): what OpenCV's rgbd::registerDepth does without dilation,
  // with the rays precomputed (bench_edges: about twice as fast)
  const Intrinsics& Kd = camera.intrinsics;
  const Eigen::Matrix3f Rf = R.cast<float>();
  const Eigen::Vector3f t = camera.to_color.translation().cast<float>();
  std::vector<float> ray_x(std::size_t(depth.cols())), ray_y(std::size_t(depth.rows()));
  for (int u = 0; u < depth.cols(); ++u) ray_x[std::size_t(u)] = float((u - Kd.cx) / Kd.fx);
  for (int v = 0; v < depth.rows(); ++v) ray_y[std::size_t(v)] = float((v - Kd.cy) / Kd.fy);
  const float fx = float(color.fx), fy = float(color.fy), cx = float(color.cx), cy = float(color.cy);
  DepthImage registered(rows, cols, INFINITY);
  for (int v = 0; v < depth.rows(); ++v) {
    const float* d = depth.ptr(v, 0);
    // R (x z, y z, z) + t = z (R (x, y, 1)) + t: the row's part of R (x, y, 1) once per row
    const Eigen::Vector3f row = Rf.col(1) * ray_y[std::size_t(v)] + Rf.col(2);
    for (int u = 0; u < depth.cols(); ++u) {
      const float z = d[u];
      if (!(z > kMinRange && z < kMaxRange)) continue;
      const Eigen::Vector3f p = z * (Rf.col(0) * ray_x[std::size_t(u)] + row) + t;
      if (!(p.z() > kMinRange)) continue;
      const float inv = 1.f / p.z();
      const int uc = int(std::lround(fx * p.x() * inv + cx)), vc = int(std::lround(fy * p.y() * inv + cy));
      if (uc < 0 || vc < 0 || uc >= cols || vc >= rows) continue;
      float& out = registered(vc, uc);
      out = std::min(out, p.z());
    }
  }
  for (std::size_t i = 0; i < registered.pixels(); ++i)
    if (!(registered.data()[i] < kMaxRange)) registered.data()[i] = std::nanf("");
  return registered;
}

}  // namespace mereo::signal
