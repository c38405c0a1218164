// Registration of depth to the colour camera (see register.hpp).
#include "mereo/signal/register.hpp"

#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/rgbd.hpp>

#include "mereo/core/error.hpp"

namespace mereo::signal {

namespace {
cv::Matx33d camera_matrix(const Intrinsics& K) { return {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1}; }
}  // namespace

DepthImage register_depth(const DepthImage& depth, const DepthCamera& camera, const Intrinsics& color, int rows,
                          int cols) {
  if (rows <= 0 || cols <= 0) throw InputError("register_depth: the colour image is empty");
  if (depth.empty()) throw InputError("register_depth: the depth image is empty");
  if (const auto p = camera.intrinsics.problem(); !p.empty()) throw InputError("register_depth: the depth camera: " + p);
  if (const auto p = color.problem(); !p.empty()) throw InputError("register_depth: the colour camera: " + p);
  const Eigen::Matrix3d R = camera.to_color.linear();
  if (!camera.to_color.matrix().allFinite() || (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
      R.determinant() < 0)
    throw InputError("register_depth: the depth-to-colour transform is not a rotation and a translation");
  // missing depth is 0 to OpenCV (a NaN would project nowhere defined)
  cv::Mat in(depth.rows(), depth.cols(), CV_32F);
  for (int v = 0; v < depth.rows(); ++v)
    for (int u = 0; u < depth.cols(); ++u) {
      const float z = depth(v, u);
      in.at<float>(v, u) = std::isfinite(z) && z > 0 ? z : 0.f;
    }
  cv::Matx44d Rt;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) Rt(i, j) = camera.to_color.matrix()(i, j);
  cv::Mat out;
  cv::rgbd::registerDepth(camera_matrix(camera.intrinsics), camera_matrix(color), cv::noArray(), Rt, in,
                          cv::Size(cols, rows), out, false);
  DepthImage registered(rows, cols, std::nanf(""));
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      const float z = out.at<float>(v, u);
      if (std::isfinite(z) && z > kMinRange && z < kMaxRange) registered(v, u) = z;
    }
  return registered;
}

}  // namespace mereo::signal
