// Edge-preserving depth filter (bilateral, depth-dependent range kernel).
#include "mereo/signal/depth_filter.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/vectorize.hpp"
#include "mereo/core/error.hpp"

namespace mereo::signal {

namespace {

/// One window offset's contribution to n output pixels of a row: q holds their neighbours at the
/// offset, z their own depth, w is the offset's spatial weight; accumulates the
/// weights into sw and the weighted differences from the centre into sz. No branch nor table
/// look-up in the loop, so that it vectorizes. The range weight exp(-x), x = dz^2 / (2 sigma_r^2),
/// is (1 - x / 256)^256 (inv = 1 / (512 sigma_r^2)): within 0.8% of it for x <= 2, below 4e-4
/// beyond x = 8.
MEREO_VECTOR_CLONES void accumulate(const float* __restrict q, const float* __restrict z, const float* __restrict inv,
                                    const float* __restrict jump, float w, int n, float* __restrict sw,
                                    float* __restrict sz) {
  for (int u = 0; u < n; ++u) {
    const float dz = q[u] - z[u];
    float e = std::max(0.f, 1.f - dz * dz * inv[u]);
    e *= e, e *= e, e *= e, e *= e, e *= e, e *= e, e *= e, e *= e;
    const bool near = std::abs(dz) <= jump[u];  // false for a NaN neighbour or centre
    const float we = near ? w * e : 0.f;
    sw[u] += we;
    sz[u] += near ? we * dz : 0.f;
  }
}

/// A depth image whose every value the caller writes: no fill first.
DepthImage unfilled(int rows, int cols) {
  return DepthImage(rows, cols, std::shared_ptr<float[]>(new float[std::size_t(rows) * std::size_t(cols)]));
}

}  // namespace

DepthImage filter_depth(const DepthImage& depth, const DepthFilterOptions& o) {
  if (o.radius < 1 || o.radius > 10)
    throw InputError("filter_depth: radius must be in [1, 10], got " + std::to_string(o.radius));
  if (!(o.sigma_space > 0) || !(o.sigma_depth > 0) || !(o.depth_change_factor > 0))
    throw InputError("filter_depth: sigma_space, sigma_depth and depth_change_factor must be > 0");
  const int H = depth.rows(), W = depth.cols(), r = o.radius;
  DepthImage out = unfilled(H, W);  // every row written below
  // spatial weights, one table
  const int side = 2 * r + 1;
  std::vector<float> ws(std::size_t(side) * side);
  for (int dv = -r; dv <= r; ++dv)
    for (int du = -r; du <= r; ++du)
      ws[std::size_t(dv + r) * side + (du + r)] = float(std::exp(-(du * du + dv * dv) / (2 * o.sigma_space * o.sigma_space)));
  const float sd = float(o.sigma_depth), cut = float(o.depth_change_factor);
  // the depth with every invalid pixel NaN: a NaN neighbour or centre then fails the jump test
  // below without a branch
  DepthImage clean = unfilled(H, W);
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* d = depth.ptr(v, 0);
      float* c = clean.ptr(v, 0);
      for (int u = 0; u < W; ++u) c[u] = valid_depth(d[u]) ? d[u] : kNaN;
    }
  });
  // each output row accumulated one window offset at a time over the whole row (accumulate)
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    const std::size_t n = std::size_t(W);
    std::vector<float> inv(n), jump(n), sw(n), sz(n);
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* z = clean.ptr(v, 0);
      for (int u = 0; u < W; ++u) {
        const float sr = sd * z[u] * z[u];
        inv[u] = 1.f / (512.f * sr * sr), jump[u] = cut * z[u];
        sw[u] = 0.f, sz[u] = 0.f;
      }
      for (int vv = std::max(0, v - r); vv <= std::min(H - 1, v + r); ++vv) {
        const float* row = clean.ptr(vv, 0);
        for (int du = -r; du <= r; ++du) {
          const int u0 = std::max(0, -du), u1 = std::min(W, W - du);
          accumulate(row + u0 + du, z + u0, inv.data() + u0, jump.data() + u0, ws[std::size_t(vv - v + r) * side + (du + r)],
                     u1 - u0, sw.data() + u0, sz.data() + u0);
        }
      }
      float* o_row = out.ptr(v, 0);
      // the weighted mean of the differences, added to the centre (sw >= 1: the centre has weight
      // 1); a NaN centre stays NaN
      for (int u = 0; u < W; ++u) o_row[u] = z[u] + sz[u] / sw[u];
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
