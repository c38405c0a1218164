// The active-stereo depth model (StereoModel in mereo/synthetic/scene.hpp): what a RealSense
// D4xx camera's block matcher makes of a scene. Every random choice is a hash of the seed, the
// frame, the pixel (or a lattice node) and a stream: deterministic per seed and frame, on any
// number of threads.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "depth_models.hpp"

namespace mereo::synthetic::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// A disparity step between neighbours larger than this is a depth edge for the matcher (its
/// window sees two surfaces), pixels.
constexpr double kEdgePx = 1.0;
/// Surfaces seen at grazing angles lose depth with a probability rising from 0 at the first
/// angle to 1 at the second, degrees (steeper than the Kinect's: stereo matches slanted
/// surfaces better than a structured-light decoder).
constexpr double kGrazingFrom = 75.0, kGrazingTo = 88.0;

enum Stream : std::uint64_t {
  kPatch = 101, kPixel = 102, kFatten = 103, kThin = 104, kDark = 105, kGrazing = 106
};

double gauss_of(std::uint64_t seed, int frame, std::uint64_t key, Stream s) {
  const std::uint64_t f = std::uint64_t(std::int64_t(frame));
  const double u1 = 1.0 - unit_from_bits(hash4(seed, f, key, s));  // (0, 1]
  const double u2 = unit_from_bits(hash4(seed, f, key, s + 0x100));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * kPi * u2);
}

double uniform_of(std::uint64_t seed, int frame, std::uint64_t key, Stream s) {
  return unit_from_bits(hash4(seed, std::uint64_t(std::int64_t(frame)), key, s));
}

/// Smooth Gaussian noise of unit variance: normal values on two lattices of `cell` pixels,
/// turned 25 and -35 degrees from the image axes (one square lattice shows its grid), each
/// blended with smoothstep weights w and divided by sqrt(sum w^2) (so that every pixel's variance
/// is 1, not only the nodes'), the two summed and divided by sqrt 2. Its correlation length is
/// about one cell.
class SmoothNoise {
 public:
  SmoothNoise(std::uint64_t seed, int frame, Stream s, int width, int height, double cell) {
    const double angles[2] = {25.0 * kPi / 180.0, -35.0 * kPi / 180.0};
    for (int l = 0; l < 2; ++l) {
      Layer& L = layers_[l];
      L.c = std::cos(angles[l]) / cell;
      L.s = std::sin(angles[l]) / cell;
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const double u : {0.0, double(width - 1)})
        for (const double v : {0.0, double(height - 1)}) {
          const double x = L.c * u - L.s * v, y = L.s * u + L.c * v;
          x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
      L.i0 = int(std::floor(x0));
      L.j0 = int(std::floor(y0));
      L.nx = int(std::floor(x1)) - L.i0 + 2;
      L.ny = int(std::floor(y1)) - L.j0 + 2;
      L.g.resize(std::size_t(L.nx) * L.ny);
      for (int j = 0; j < L.ny; ++j)
        for (int i = 0; i < L.nx; ++i)
          L.g[std::size_t(j) * L.nx + i] =
              gauss_of(seed, frame, (std::uint64_t(l) << 62) | (std::uint64_t(j) << 31) | std::uint64_t(i), s);
    }
  }
  double operator()(int u, int v) const {
    return (layers_[0].at(u, v) + layers_[1].at(u, v)) * 0.70710678118654752440;
  }
  /// The same as a uniform value in [0, 1] (the normal distribution function of it): patches
  /// of pixels make the same random choice.
  double uniform(int u, int v) const { return 0.5 * std::erfc(-(*this)(u, v) / std::sqrt(2.0)); }

 private:
  struct Layer {
    double c = 1, s = 0;  // the turn, divided by the cell size
    int i0 = 0, j0 = 0, nx = 0, ny = 0;
    std::vector<double> g;
    double at(int u, int v) const {
      const double gx = c * u - s * v - i0, gy = s * u + c * v - j0;
      const int i = std::clamp(int(std::floor(gx)), 0, nx - 2), j = std::clamp(int(std::floor(gy)), 0, ny - 2);
      const double tx = std::clamp(gx - i, 0.0, 1.0), ty = std::clamp(gy - j, 0.0, 1.0);
      const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
      const double wx[2] = {1 - sx, sx}, wy[2] = {1 - sy, sy};
      double sum = 0, norm = 0;
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const double w = wx[a] * wy[b];
          sum += w * g[std::size_t(j + b) * nx + i + a];
          norm += w * w;
        }
      return sum / std::sqrt(norm);
    }
  };
  Layer layers_[2];
};

/// For each pixel, the length of its run of surface pixels along a row (dx = 1) or a column
/// (dy = 1) without a depth edge, when both ends of the run meet a farther surface (a ridge:
/// a thin structure in front of something); the maximum int otherwise.
void ridge_widths(const std::vector<double>& dis, const std::vector<char>& has, int W, int H, bool rows,
                  std::vector<int>& width) {
  const int lines = rows ? H : W, len = rows ? W : H;
  tbb::parallel_for(tbb::blocked_range<int>(0, lines), [&](const tbb::blocked_range<int>& r) {
    for (int line = r.begin(); line < r.end(); ++line) {
      auto at = [&](int k) { return rows ? std::size_t(line) * W + k : std::size_t(k) * W + line; };
      int s = 0;
      while (s < len) {
        if (!has[at(s)]) {
          ++s;
          continue;
        }
        int e = s;
        while (e + 1 < len && has[at(e + 1)] && std::abs(dis[at(e + 1)] - dis[at(e)]) <= kEdgePx) ++e;
        const bool ridge = s > 0 && e + 1 < len && dis[at(s - 1)] < dis[at(s)] - kEdgePx &&
                           dis[at(e + 1)] < dis[at(e)] - kEdgePx;
        for (int k = s; k <= e; ++k) width[at(k)] = ridge ? e - s + 1 : std::numeric_limits<int>::max();
        s = e + 1;
      }
    }
  });
}

}  // namespace

void stereo_depth(const RenderedRays& rays, const StereoModel& m, DepthImage& out) {
  const int W = rays.depth.cols(), H = rays.depth.rows();
  const std::size_t N = std::size_t(W) * H;
  const Intrinsics& K = rays.K;
  const double fb = K.fx * m.baseline;  // disparity (pixels) = fb / depth
  const Vec3 imager(m.baseline, 0.0, 0.0);  // the second imager, to the right of the camera

  std::vector<double> dis(N, 0.0);  // exact disparity; 0 where no surface (infinitely far)
  std::vector<char> has(N, 0);
  for (std::size_t i = 0; i < N; ++i) {
    const float z = rays.depth.data()[i];
    if (std::isnan(z)) continue;
    dis[i] = fb / z;
    has[i] = 1;
  }

  const SmoothNoise patch(rays.seed, rays.frame, kPatch, W, H, m.noise_patch);
  const SmoothNoise fatten(rays.seed, rays.frame, kFatten, W, H, m.noise_patch);
  const SmoothNoise thin(rays.seed, rays.frame, kThin, W, H, m.noise_patch);
  const SmoothNoise dark(rays.seed, rays.frame, kDark, W, H, m.noise_patch);

  // thin structures: the narrower of a pixel's row and column ridge runs
  std::vector<int> across(N), down(N);
  ridge_widths(dis, has, W, H, true, across);
  ridge_widths(dis, has, W, H, false, down);
  std::vector<char> thin_hole(N, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
    for (int v = r.begin(); v < r.end(); ++v)
      for (int u = 0; u < W; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        if (!has[i] || m.thin_px <= 0) continue;
        const double w = std::min(across[i], down[i]);
        const double p = std::clamp((2 * m.thin_px - w) / m.thin_px, 0.0, 1.0);
        thin_hole[i] = p > 0 && thin.uniform(u, v) < p;
      }
  });

  const int max_fattening = int(std::floor(m.fattening_px));
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
    for (int v = r.begin(); v < r.end(); ++v) {
      for (int u = 0; u < W; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        out(v, u) = kNaN;
        double d = 0.0;
        bool fattened = false;
        // (1) edge fattening: a nearer surface starts within this row's strip to the right
        if (max_fattening >= 1) {
          const double strip = 1.0 + (m.fattening_px - 1.0) * fatten.uniform(u, v);
          for (int k = 1; k <= max_fattening && u + k < W; ++k) {
            const std::size_t j = i + k;
            if (std::abs(dis[j] - dis[j - 1]) <= kEdgePx && has[j] == has[j - 1]) continue;
            if (dis[j] > dis[j - 1] + kEdgePx && dis[j] > dis[i] + kEdgePx && k <= strip && !thin_hole[j]) {
              d = dis[j];
              fattened = true;
            }
            break;  // the first edge decides
          }
        }
        if (!fattened) {
          if (!has[i] || thin_hole[i]) continue;  // (2) nothing there; a thin structure
          // (3) grazing angles
          const double ang = std::acos(std::clamp(double(rays.shade[i]), 0.0, 1.0)) * 180.0 / kPi;
          const double p_grazing = std::clamp((ang - kGrazingFrom) / (kGrazingTo - kGrazingFrom), 0.0, 1.0);
          if (p_grazing > 0 && uniform_of(rays.seed, rays.frame, i, kGrazing) < p_grazing) continue;
          // (4) dark surfaces, in patches: the colour image's luminance
          const Eigen::Vector3f& c = rays.scene.objects[rays.hit_obj[i]].color;
          const double lum = (0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]) *
                             (0.2 + 0.8 * std::max(0.0f, rays.shade[i]));
          const double p_dark = m.dark_albedo > 0 ? std::clamp((m.dark_albedo - lum) / (0.5 * m.dark_albedo), 0.0, 1.0) : 0.0;
          if (p_dark > 0 && dark.uniform(u, v) < p_dark) continue;
          // (5) what the second imager cannot see
          const Vec3 dir = Vec3((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).normalized();
          const Vec3 P = rays.ray_t[i] * dir;
          Vec3 to = imager - P;
          const double dist = to.norm();
          to /= dist;
          if (cast_any(rays.scene, P, to, 1e-5, dist - 1e-6)) continue;
          d = dis[i];
        }
        // (6) disparity noise, smooth and per pixel, then subpixel steps; (7) range
        d += m.patch_noise_px * patch(u, v) + m.pixel_noise_px * gauss_of(rays.seed, rays.frame, i, kPixel);
        d = std::round(d * m.subpixel) / m.subpixel;
        if (!(d > 0)) continue;
        const double z = fb / d;
        if (z < m.min_range || z > m.max_range) continue;
        out(v, u) = float(z);
      }
    }
  });
}

}  // namespace mereo::synthetic::detail
