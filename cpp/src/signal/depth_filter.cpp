// Edge-preserving depth filter (bilateral, depth-dependent range kernel).
#include "mereo/signal/depth_filter.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mereo/core/error.hpp"

namespace mereo::signal {

DepthImage filter_depth(const DepthImage& depth, const DepthFilterOptions& o) {
  if (o.radius < 1 || o.radius > 10)
    throw InputError("filter_depth: radius must be in [1, 10], got " + std::to_string(o.radius));
  if (!(o.sigma_space > 0) || !(o.sigma_depth > 0) || !(o.depth_change_factor > 0))
    throw InputError("filter_depth: sigma_space, sigma_depth and depth_change_factor must be > 0");
  const int H = depth.rows(), W = depth.cols(), r = o.radius;
  DepthImage out(H, W, kNaN);
  // spatial weights, one table
  std::vector<float> ws(std::size_t(2 * r + 1) * (2 * r + 1));
  for (int dv = -r; dv <= r; ++dv)
    for (int du = -r; du <= r; ++du)
      ws[std::size_t(dv + r) * (2 * r + 1) + (du + r)] =
          float(std::exp(-(du * du + dv * dv) / (2 * o.sigma_space * o.sigma_space)));
  const float sd = float(o.sigma_depth), cut = float(o.depth_change_factor);
  // range weights exp(-x), x = dz^2 / (2 sigma_r^2) in [0, 8), from a table of 512 steps (the
  // weight beyond x = 8 is below 0.0004 and taken as 0)
  constexpr int kSteps = 512;
  constexpr float kMaxX = 8.f, kScale = kSteps / kMaxX;
  std::vector<float> range_lut(kSteps + 1);
  for (int i = 0; i <= kSteps; ++i) range_lut[i] = i == kSteps ? 0.f : float(std::exp(-(i + 0.5) / kScale));
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const int v0 = std::max(0, v - r), v1 = std::min(H - 1, v + r);
      for (int u = 0; u < W; ++u) {
        const float z = depth(v, u);
        if (!valid_depth(z)) continue;  // missing or out of any sensor's range: stays NaN
        const float sr = sd * z * z, inv = kScale * 0.5f / (sr * sr), t = cut * z;
        const int u0 = std::max(0, u - r), u1 = std::min(W - 1, u + r);
        float sw = 0.f, sz = 0.f;
        for (int vv = v0; vv <= v1; ++vv) {
          const float* row = depth.ptr(vv, 0);
          const float* wrow = ws.data() + std::size_t(vv - v + r) * (2 * r + 1) + r;
          for (int uu = u0; uu <= u1; ++uu) {
            const float q = row[uu];
            const float dz = q - z;
            if (!valid_depth(q) || std::abs(dz) > t) continue;
            const float x = dz * dz * inv;
            const int bin = x < float(kSteps) ? int(x) : kSteps;  // NaN or beyond the table: weight 0
            const float w = wrow[uu - u] * range_lut[bin];
            sw += w;
            sz += w * q;
          }
        }
        out(v, u) = sz / sw;  // sw >= 1: the centre has weight 1
      }
    }
  });
  return out;
}

Frame filter_depth(const Frame& frame, const DepthFilterOptions& o) {
  Frame out = frame;
  out.depth = filter_depth(frame.depth, o);
  if (!frame.cloud.empty()) {
    if (!frame.cloud.same_size(frame.depth))
      throw InputError(frame.source + ": cloud and depth differ in size");
    Cloud cloud = frame.cloud.clone();
    const float* d0 = frame.depth.data();
    const float* d1 = out.depth.data();
    float* p = cloud.data();
    for (std::size_t i = 0; i < cloud.pixels(); ++i, p += 3) {
      if (!(d0[i] > 0.f) || !(d1[i] > 0.f)) continue;
      const float s = d1[i] / d0[i];
      p[0] *= s, p[1] *= s, p[2] *= s;
    }
    out.cloud = cloud;
  }
  return out;
}

}  // namespace mereo::signal
