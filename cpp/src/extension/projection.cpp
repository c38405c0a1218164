#include "mereo/extension/projection.hpp"

#include <cmath>

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mereo/core/error.hpp"

namespace mereo::extension {

Cloud back_project(const DepthImage& depth, const Intrinsics& K) {
  Cloud cloud(depth.rows(), depth.cols(), kNaN);
  const float ifx = float(1.0 / K.fx), ify = float(1.0 / K.fy);
  const float cx = float(K.cx), cy = float(K.cy);
  tbb::parallel_for(tbb::blocked_range<int>(0, depth.rows(), 16), [&](const auto& range) {
    for (int v = range.begin(); v < range.end(); ++v) {
      const float* d = depth.ptr(v, 0);
      float* p = cloud.ptr(v, 0);
      for (int u = 0; u < depth.cols(); ++u, p += 3) {
        const float z = d[u];
        if (!valid_depth(z)) continue;  // missing and out-of-range depth stay NaN
        p[0] = (float(u) - cx) * z * ifx;
        p[1] = (float(v) - cy) * z * ify;
        p[2] = z;
      }
    }
  });
  return cloud;
}

Cloud back_project(const Frame& frame) {
  if (!frame.cloud.empty()) return frame.cloud;
  return back_project(frame.depth, frame.intrinsics);
}

DepthImage cloud_depth(const Cloud& cloud) {
  DepthImage depth(cloud.rows(), cloud.cols(), kNaN);
  const float* p = cloud.data();
  float* d = depth.data();
  for (std::size_t i = 0; i < depth.pixels(); ++i, p += 3) {
    if (valid_point(p)) d[i] = p[2];
  }
  return depth;
}

Intrinsics fit_intrinsics(const Cloud& cloud, double* max_residual_px) {
  // Two independent 2-parameter least-squares fits: u = fx * (x/z) + cx, v = fy * (y/z) + cy.
  Eigen::Matrix2d Au = Eigen::Matrix2d::Zero(), Av = Eigen::Matrix2d::Zero();
  Eigen::Vector2d bu = Eigen::Vector2d::Zero(), bv = Eigen::Vector2d::Zero();
  std::size_t n = 0;
  for (int v = 0; v < cloud.rows(); ++v) {
    for (int u = 0; u < cloud.cols(); ++u) {
      const float* p = cloud.ptr(v, u);
      if (!valid_point(p)) continue;
      const double a = double(p[0]) / p[2], b = double(p[1]) / p[2];
      Au += Eigen::Vector2d(a, 1) * Eigen::RowVector2d(a, 1);
      bu += Eigen::Vector2d(a, 1) * double(u);
      Av += Eigen::Vector2d(b, 1) * Eigen::RowVector2d(b, 1);
      bv += Eigen::Vector2d(b, 1) * double(v);
      ++n;
    }
  }
  if (n < 10) throw InputError("cannot fit intrinsics: the cloud has fewer than 10 valid points");
  const Eigen::Vector2d su = Au.ldlt().solve(bu), sv = Av.ldlt().solve(bv);
  Intrinsics K{su[0], sv[0], su[1], sv[1]};
  if (max_residual_px) {
    double worst = 0;
    for (int v = 0; v < cloud.rows(); ++v)
      for (int u = 0; u < cloud.cols(); ++u) {
        const float* p = cloud.ptr(v, u);
        if (!valid_point(p)) continue;
        worst = std::max({worst, std::abs(K.fx * p[0] / p[2] + K.cx - u),
                          std::abs(K.fy * p[1] / p[2] + K.cy - v)});
      }
    *max_residual_px = worst;
  }
  if (!K.valid()) throw InputError("cannot fit intrinsics: the cloud is not a pinhole projection");
  return K;
}

}  // namespace mereo::extension
