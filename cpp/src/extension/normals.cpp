// Per-pixel normals of organized clouds: a fast least-squares tangent method and a covariance
// (PCA) method through integral images, both aware of depth discontinuities.
//
// Common to both: a pixel is an *edge* pixel when it is missing, when a 4-neighbour is missing,
// or when a 4-neighbour's depth differs by more than depth_change_factor * z. A capped
// chessboard (L-infinity) distance to the nearest edge pixel (the image border counts as one)
// then says how large a square window around each pixel may be without containing an edge
// pixel, hence without crossing a depth jump (the idea of PCL's IntegralImageNormalEstimation,
// Holzer et al. 2012, with an exact L-infinity distance instead of a chamfer one). Pixels at
// an edge (distance <= 1) get a normal from their own window restricted to the points within
// depth_change_factor * z of their own depth (the depth test of LINEMOD, Hinterstoisser et al.
// 2012).
#include "mereo/extension/normals.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mereo/core/error.hpp"

namespace mereo::extension {
namespace {

inline bool valid_point(const float* p) {
  return p[2] > 0.f && std::isfinite(p[2]) && std::isfinite(p[0]) && std::isfinite(p[1]);
}

/// Capped L-infinity distance (in pixels, <= cap) of every pixel to the nearest edge pixel;
/// outside the image counts as edge. Edge pixels have distance 0.
std::vector<std::uint8_t> edge_distance(const Cloud& cloud, double factor, int cap) {
  const int H = cloud.rows(), W = cloud.cols();
  std::vector<std::uint8_t> h(std::size_t(H) * W), dist(std::size_t(H) * W);
  const float f = float(factor);
  // rows: edge flags and the horizontal distance
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<std::uint8_t> edge(W);
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* row = cloud.ptr(v, 0);
      const float* up = v > 0 ? cloud.ptr(v - 1, 0) : nullptr;
      const float* down = v + 1 < H ? cloud.ptr(v + 1, 0) : nullptr;
      for (int u = 0; u < W; ++u) {
        const float* p = row + 3 * u;
        if (!valid_point(p)) {
          edge[u] = 1;
          continue;
        }
        const float z = p[2], t = f * z;
        bool e = false;
        auto check = [&](const float* q) {
          if (!valid_point(q) || std::abs(q[2] - z) > t) e = true;
        };
        if (u > 0) check(p - 3);
        if (u + 1 < W) check(p + 3);
        if (up) check(up + 3 * u);
        if (down) check(down + 3 * u);
        edge[u] = e;
      }
      std::uint8_t* hr = h.data() + std::size_t(v) * W;
      int run = 0;  // distance to the virtual edge at u = -1
      for (int u = 0; u < W; ++u) {
        run = edge[u] ? 0 : std::min(run + 1, cap);
        hr[u] = std::uint8_t(run);
      }
      run = 0;
      for (int u = W - 1; u >= 0; --u) {
        run = edge[u] ? 0 : std::min(run + 1, cap);
        hr[u] = std::min<std::uint8_t>(hr[u], std::uint8_t(run));
      }
    }
  });
  // columns: d(v, u) = min over dv of max(|dv|, h(v + dv, u)), rows outside the image = edge
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      std::uint8_t* d = dist.data() + std::size_t(v) * W;
      const std::uint8_t border = std::uint8_t(std::min({cap, v + 1, H - v}));
      const std::uint8_t* h0 = h.data() + std::size_t(v) * W;
      for (int u = 0; u < W; ++u) d[u] = std::min(border, h0[u]);
      for (int k = 1; k < cap; ++k) {
        const std::uint8_t kk = std::uint8_t(k);
        if (v - k >= 0) {
          const std::uint8_t* hr = h.data() + std::size_t(v - k) * W;
          for (int u = 0; u < W; ++u) d[u] = std::min(d[u], std::max(kk, hr[u]));
        }
        if (v + k < H) {
          const std::uint8_t* hr = h.data() + std::size_t(v + k) * W;
          for (int u = 0; u < W; ++u) d[u] = std::min(d[u], std::max(kk, hr[u]));
        }
      }
    }
  });
  return dist;
}

/// Writes n (any length) normalised and turned towards the camera at p; NaN if degenerate.
inline void store_normal(double nx, double ny, double nz, const float* p, float* out) {
  const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (!(len > 0) || !std::isfinite(len)) {
    out[0] = out[1] = out[2] = kNaN;
    return;
  }
  double s = 1.0 / len;
  if (nx * p[0] + ny * p[1] + nz * p[2] > 0) s = -s;
  out[0] = float(nx * s);
  out[1] = float(ny * s);
  out[2] = float(nz * s);
}

/// Eigenvector of the smallest eigenvalue of a symmetric positive semi-definite 3x3 matrix, by
/// power iteration on its adjugate (whose dominant eigenvector it is: adj(C) = sum over i of
/// (product of the other two eigenvalues) e_i e_i^T). False when C has rank < 2.
inline bool smallest_eigenvector(double c00, double c01, double c02, double c11, double c12,
                                 double c22, double n[3]) {
  const double tr = c00 + c11 + c22;
  if (!(tr > 0)) return false;
  const double s = 1.0 / tr;
  c00 *= s, c01 *= s, c02 *= s, c11 *= s, c12 *= s, c22 *= s;
  const double a00 = c11 * c22 - c12 * c12, a01 = c02 * c12 - c01 * c22,
               a02 = c01 * c12 - c02 * c11, a11 = c00 * c22 - c02 * c02,
               a12 = c01 * c02 - c00 * c12, a22 = c00 * c11 - c01 * c01;
  double x, y, z;
  if (a00 >= a11 && a00 >= a22) {
    x = a00, y = a01, z = a02;
  } else if (a11 >= a22) {
    x = a01, y = a11, z = a12;
  } else {
    x = a02, y = a12, z = a22;
  }
  if (!(std::max({a00, a11, a22}) > 1e-14)) return false;
  for (int it = 0; it < 2; ++it) {
    const double l = 1.0 / std::sqrt(x * x + y * y + z * z);
    x *= l, y *= l, z *= l;
    const double nx = a00 * x + a01 * y + a02 * z, ny = a01 * x + a11 * y + a12 * z,
                 nz = a02 * x + a12 * y + a22 * z;
    x = nx, y = ny, z = nz;
  }
  n[0] = x, n[1] = y, n[2] = z;
  return true;
}

/// The points of the window of side `side` around (v, u) that lie within `factor` * z of the
/// centre's depth, passed to `add(du, dv, dx, dy, dz)` relative to the centre. Returns the count.
template <typename Add>
int for_each_near(const Cloud& cloud, int v, int u, int side, double factor, Add&& add) {
  const float* c = cloud.ptr(v, u);
  const float t = float(factor) * c[2];
  const int r = side / 2;
  const int v0 = std::max(0, v - r), v1 = std::min(cloud.rows() - 1, v + r);
  const int u0 = std::max(0, u - r), u1 = std::min(cloud.cols() - 1, u + r);
  int n = 0;
  for (int vv = v0; vv <= v1; ++vv) {
    const float* q = cloud.ptr(vv, u0);
    for (int uu = u0; uu <= u1; ++uu, q += 3) {
      if (!valid_point(q) || std::abs(q[2] - c[2]) > t) continue;
      add(double(uu - u), double(vv - v), double(q[0] - c[0]), double(q[1] - c[1]),
          double(q[2] - c[2]));
      ++n;
    }
  }
  return n;
}

/// Masked least-squares tangents at an edge pixel: fits p = p0 + a du + b dv to the accepted
/// points, n = a x b.
void explicit_tangents(const Cloud& cloud, int v, int u, int side, const NormalOptions& o,
                       float* out) {
  double m[6] = {0, 0, 0, 0, 0, 0};  // N, du, dv, du du, du dv, dv dv
  double sc[3] = {0, 0, 0}, su[3] = {0, 0, 0}, sv[3] = {0, 0, 0};
  const int n = for_each_near(cloud, v, u, side, o.depth_change_factor,
                              [&](double du, double dv, double x, double y, double z) {
                                m[0] += 1, m[1] += du, m[2] += dv;
                                m[3] += du * du, m[4] += du * dv, m[5] += dv * dv;
                                const double c[3] = {x, y, z};
                                for (int k = 0; k < 3; ++k) {
                                  sc[k] += c[k], su[k] += du * c[k], sv[k] += dv * c[k];
                                }
                              });
  const float* p = cloud.ptr(v, u);
  out[0] = out[1] = out[2] = kNaN;
  if (n < std::max(3, o.min_points)) return;
  // inverse of the symmetric M = [[N, Su, Sv], [Su, Suu, Suv], [Sv, Suv, Svv]] (rows 1 and 2)
  const double N = m[0], Su = m[1], Sv = m[2], Suu = m[3], Suv = m[4], Svv = m[5];
  const double c00 = Suu * Svv - Suv * Suv, c01 = Sv * Suv - Su * Svv, c02 = Su * Suv - Sv * Suu;
  const double det = N * c00 + Su * c01 + Sv * c02;
  if (!(det > 0.5)) return;  // an integer; 0 when the pixels are collinear
  const double c11 = N * Svv - Sv * Sv, c12 = Su * Sv - N * Suv, c22 = N * Suu - Su * Su;
  double a[3], b[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = c01 * sc[k] + c11 * su[k] + c12 * sv[k];
    b[k] = c02 * sc[k] + c12 * su[k] + c22 * sv[k];
  }
  store_normal(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0], p,
               out);
}

/// PCA of the accepted points of an edge pixel's window.
void explicit_covariance(const Cloud& cloud, int v, int u, int side, const NormalOptions& o,
                         float* out) {
  double s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  const int n = for_each_near(cloud, v, u, side, o.depth_change_factor,
                              [&](double, double, double x, double y, double z) {
                                s[0] += x, s[1] += y, s[2] += z;
                                s[3] += x * x, s[4] += x * y, s[5] += x * z;
                                s[6] += y * y, s[7] += y * z, s[8] += z * z;
                              });
  out[0] = out[1] = out[2] = kNaN;
  if (n < std::max(3, o.min_points)) return;
  const double in = 1.0 / n, mx = s[0] * in, my = s[1] * in, mz = s[2] * in;
  double e[3];
  if (!smallest_eigenvector(s[3] * in - mx * mx, s[4] * in - mx * my, s[5] * in - mx * mz,
                            s[6] * in - my * my, s[7] * in - my * mz, s[8] * in - mz * mz, e))
    return;
  store_normal(e[0], e[1], e[2], cloud.ptr(v, u), out);
}

// ---- fast: separable least-squares tangents ----------------------------------------------

void fast_normals(const Cloud& cloud, const NormalOptions& o, NormalMap& out) {
  const int H = cloud.rows(), W = cloud.cols();
  const int r = o.window / 2;
  const auto dist = edge_distance(cloud, o.depth_change_factor, r + 1);
  const int block = 32;
  const int blocks = (H + block - 1) / block;
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& br) {
    // per row of the block plus margins: SoA x y z, then 12 horizontal channels
    // (window: sum c, sum du*c; 3x3: sum c, sum du*c) for c in x, y, z
    std::vector<float> soa(3 * std::size_t(W));
    std::vector<float> hbuf;
    std::vector<float> acc(12 * std::size_t(W));
    for (int b = br.begin(); b < br.end(); ++b) {
      const int v0 = b * block, v1 = std::min(H, v0 + block);
      const int ya = std::max(0, v0 - r), yb = std::min(H, v1 + r);
      hbuf.assign(std::size_t(yb - ya) * 12 * W, 0.f);
      for (int y = ya; y < yb; ++y) {
        const float* row = cloud.ptr(y, 0);
        float* X = soa.data();
        float* Y = X + W;
        float* Z = Y + W;
        for (int u = 0; u < W; ++u) {
          const float* p = row + 3 * u;
          const bool ok = valid_point(p);
          X[u] = ok ? p[0] : 0.f;
          Y[u] = ok ? p[1] : 0.f;
          Z[u] = ok ? p[2] : 0.f;
        }
        float* hr = hbuf.data() + std::size_t(y - ya) * 12 * W;
        for (int c = 0; c < 3; ++c) {
          const float* P = soa.data() + std::size_t(c) * W;
          float* S0 = hr + std::size_t(4 * c + 0) * W;  // window sum
          float* S1 = hr + std::size_t(4 * c + 1) * W;  // window sum of du * c
          float* T0 = hr + std::size_t(4 * c + 2) * W;  // 3x3 sum
          float* T1 = hr + std::size_t(4 * c + 3) * W;  // 3x3 sum of du * c
          for (int u = 1; u + 1 < W; ++u) {
            T0[u] = P[u - 1] + P[u] + P[u + 1];
            T1[u] = P[u + 1] - P[u - 1];
          }
          for (int u = r; u + r < W; ++u) {
            float s0 = P[u], s1 = 0.f;
            for (int k = 1; k <= r; ++k) {
              s0 += P[u + k] + P[u - k];
              s1 += float(k) * (P[u + k] - P[u - k]);
            }
            S0[u] = s0;
            S1[u] = s1;
          }
        }
      }
      auto hrow = [&](int y, int ch) { return hbuf.data() + (std::size_t(y - ya) * 12 + ch) * W; };
      for (int v = v0; v < v1; ++v) {
        // acc: [A_x A_y A_z B_x B_y B_z] for the window, then the same for 3x3
        std::fill(acc.begin(), acc.end(), 0.f);
        if (v - r >= 0 && v + r < H) {
          for (int c = 0; c < 3; ++c) {
            float* A = acc.data() + std::size_t(c) * W;
            float* B = acc.data() + std::size_t(3 + c) * W;
            for (int dv = -r; dv <= r; ++dv) {
              const float* S1 = hrow(v + dv, 4 * c + 1);
              for (int u = 0; u < W; ++u) A[u] += S1[u];
            }
            for (int k = 1; k <= r; ++k) {
              const float* Sp = hrow(v + k, 4 * c);
              const float* Sm = hrow(v - k, 4 * c);
              const float fk = float(k);
              for (int u = 0; u < W; ++u) B[u] += fk * (Sp[u] - Sm[u]);
            }
          }
        }
        if (v >= 1 && v + 1 < H && r > 1) {
          for (int c = 0; c < 3; ++c) {
            float* A = acc.data() + std::size_t(6 + c) * W;
            float* B = acc.data() + std::size_t(9 + c) * W;
            const float *Tm = hrow(v - 1, 4 * c + 3), *T0 = hrow(v, 4 * c + 3),
                        *Tp = hrow(v + 1, 4 * c + 3);
            const float *Gp = hrow(v + 1, 4 * c + 2), *Gm = hrow(v - 1, 4 * c + 2);
            for (int u = 0; u < W; ++u) {
              A[u] = Tm[u] + T0[u] + Tp[u];
              B[u] = Gp[u] - Gm[u];
            }
          }
        }
        const std::uint8_t* d = dist.data() + std::size_t(v) * W;
        const float* row = cloud.ptr(v, 0);
        float* nrow = out.ptr(v, 0);
        for (int u = 0; u < W; ++u) {
          const float* p = row + 3 * u;
          float* n = nrow + 3 * u;
          if (d[u] > r || (d[u] >= 2 && r > 1)) {
            const int off = d[u] > r ? 0 : 6;
            const float ax = acc[(off + 0) * W + u], ay = acc[(off + 1) * W + u],
                        az = acc[(off + 2) * W + u];
            const float bx = acc[(off + 3) * W + u], by = acc[(off + 4) * W + u],
                        bz = acc[(off + 5) * W + u];
            store_normal(double(ay * bz - az * by), double(az * bx - ax * bz),
                         double(ax * by - ay * bx), p, n);
          } else if (valid_point(p)) {
            explicit_tangents(cloud, v, u, std::min(o.window, 5), o, n);
          } else {
            n[0] = n[1] = n[2] = kNaN;
          }
        }
      }
    }
  });
}

// ---- covariance: integral images of first and second moments ------------------------------

void covariance_normals(const Cloud& cloud, const NormalOptions& o, NormalMap& out) {
  const int H = cloud.rows(), W = cloud.cols();
  const int smax = o.adaptive_window ? 2 * o.window + 1 : o.window;
  const int rmax = smax / 2;
  const auto dist = edge_distance(cloud, o.depth_change_factor, std::min(rmax + 1, 255));
  const int block = std::max(32, 4 * rmax);
  const int blocks = (H + block - 1) / block;
  constexpr int C = 9;  // x y z xx xy xz yy yz zz
  const int stride = (W + 1) * C;
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& br) {
    std::vector<double> ii;
    for (int b = br.begin(); b < br.end(); ++b) {
      const int v0 = b * block, v1 = std::min(H, v0 + block);
      const int ya = std::max(0, v0 - rmax), yb = std::min(H, v1 + rmax);
      // ii row j (0..yb-ya) = sums over rows [ya, ya + j) and columns [0, u)
      ii.assign(std::size_t(yb - ya + 1) * stride, 0.0);
      // a reference depth for the strip keeps the second moments small
      for (int y = ya; y < yb; ++y) {
        const float* row = cloud.ptr(y, 0);
        const double* prev = ii.data() + std::size_t(y - ya) * stride;
        double* cur = ii.data() + std::size_t(y - ya + 1) * stride;
        double run[C] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (int u = 0; u < W; ++u) {
          const float* p = row + 3 * u;
          if (valid_point(p)) {
            const double x = p[0], yy = p[1], z = p[2];
            run[0] += x, run[1] += yy, run[2] += z;
            run[3] += x * x, run[4] += x * yy, run[5] += x * z;
            run[6] += yy * yy, run[7] += yy * z, run[8] += z * z;
          }
          double* c = cur + (u + 1) * C;
          const double* pc = prev + (u + 1) * C;
          for (int k = 0; k < C; ++k) c[k] = pc[k] + run[k];
        }
      }
      for (int v = v0; v < v1; ++v) {
        const std::uint8_t* d = dist.data() + std::size_t(v) * W;
        const float* row = cloud.ptr(v, 0);
        float* nrow = out.ptr(v, 0);
        for (int u = 0; u < W; ++u) {
          const float* p = row + 3 * u;
          float* n = nrow + 3 * u;
          if (!valid_point(p)) {
            n[0] = n[1] = n[2] = kNaN;
            continue;
          }
          int side = o.window;
          if (o.adaptive_window) {
            side = int(std::lround(o.window * o.reference_depth / p[2]));
            side = std::clamp(side | 1, 3, smax);
          }
          const int r = std::min(side / 2, int(d[u]) - 1);
          if (r < 1) {
            explicit_covariance(cloud, v, u, std::min(side, 7), o, n);
            continue;
          }
          const double* t0 = ii.data() + std::size_t(v - r - ya) * stride;
          const double* t1 = ii.data() + std::size_t(v + r + 1 - ya) * stride;
          const double *a = t0 + (u - r) * C, *bb = t0 + (u + r + 1) * C;
          const double *c = t1 + (u - r) * C, *dd = t1 + (u + r + 1) * C;
          double s[C];
          for (int k = 0; k < C; ++k) s[k] = dd[k] - c[k] - bb[k] + a[k];
          const double in = 1.0 / double((2 * r + 1) * (2 * r + 1));
          const double mx = s[0] * in, my = s[1] * in, mz = s[2] * in;
          double e[3];
          if (smallest_eigenvector(s[3] * in - mx * mx, s[4] * in - mx * my, s[5] * in - mx * mz,
                                   s[6] * in - my * my, s[7] * in - my * mz,
                                   s[8] * in - mz * mz, e))
            store_normal(e[0], e[1], e[2], p, n);
          else
            n[0] = n[1] = n[2] = kNaN;
        }
      }
    }
  });
}

}  // namespace

NormalMethod normal_method(const std::string& name) {
  if (name == "fast") return NormalMethod::Fast;
  if (name == "covariance") return NormalMethod::Covariance;
  throw InputError("normals: unknown method '" + name + "' (known: fast, covariance)");
}

NormalMap estimate_normals(const Cloud& cloud, const NormalOptions& o) {
  if (o.window < 3 || o.window % 2 == 0 || o.window > 101)
    throw InputError("normals: window must be odd and in [3, 101], got " +
                     std::to_string(o.window));
  if (!(o.depth_change_factor > 0))
    throw InputError("normals: depth_change_factor must be > 0, got " +
                     std::to_string(o.depth_change_factor));
  if (o.adaptive_window && !(o.reference_depth > 0))
    throw InputError("normals: reference_depth must be > 0, got " +
                     std::to_string(o.reference_depth));
  NormalMap out(cloud.rows(), cloud.cols(), kNaN);
  if (cloud.empty()) return out;
  if (o.method == NormalMethod::Fast)
    fast_normals(cloud, o, out);
  else
    covariance_normals(cloud, o, out);
  return out;
}

}  // namespace mereo::extension
