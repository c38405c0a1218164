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

/// The depth difference that counts as a discontinuity at depth z: depth_change_factor * z, growing
/// as z^2 beyond noise_depth (structured-light noise grows with z^2, Khoshelham and Elberink 2012),
/// so that far, noisy surfaces are not broken into pieces.
struct JumpThreshold {
  float factor, inv_noise_depth;
  explicit JumpThreshold(const NormalOptions& o)
      : factor(float(o.depth_change_factor)), inv_noise_depth(float(1.0 / o.noise_depth)) {}
  float operator()(float z) const { return factor * z * std::max(1.f, z * inv_noise_depth); }
};

/// Capped L-infinity distance (in pixels, <= cap) of every pixel to the nearest edge pixel;
/// outside the image counts as edge. Edge pixels have distance 0. An edge pixel is a point with
/// a valid 4-neighbour further than factor * z in depth; with `missing_is_edge`, also a missing
/// point or one with a missing 4-neighbour.
std::vector<std::uint8_t> edge_distance(const Cloud& cloud, JumpThreshold jt, int cap,
                                        bool missing_is_edge) {
  const int H = cloud.rows(), W = cloud.cols();
  std::vector<std::uint8_t> h(std::size_t(H) * W), dist(std::size_t(H) * W);
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
          edge[u] = missing_is_edge;
          continue;
        }
        const float z = p[2], t = jt(z);
        bool e = false;
        auto check = [&](const float* q) {
          if (!valid_point(q)) {
            e = e || missing_is_edge;
          } else if (std::abs(q[2] - z) > t) {
            e = true;
          }
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

/// The same in float (the fast method's edge pixels): NaN when the length is 0 or not finite.
inline void store_normal_f(float nx, float ny, float nz, const float* p, float* out) {
  const float len2 = nx * nx + ny * ny + nz * nz;
  float s = (len2 > 0.f && len2 < INFINITY) ? 1.f / std::sqrt(len2) : kNaN;
  s = (nx * p[0] + ny * p[1] + nz * p[2] > 0.f) ? -s : s;
  out[0] = nx * s, out[1] = ny * s, out[2] = nz * s;
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
int for_each_near(const Cloud& cloud, int v, int u, int side, JumpThreshold jt, Add&& add) {
  const float* c = cloud.ptr(v, u);
  const float t = jt(c[2]);
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

/// The sums of a masked least-squares fit of p = p0 + a du + b dv over a window (explicit_tangents).
struct TangentSums {
  float N = 0, Su = 0, Sv = 0, Suu = 0, Suv = 0, Svv = 0;
  float sc[3] = {0, 0, 0}, su[3] = {0, 0, 0}, sv[3] = {0, 0, 0};
};

/// The normal a x b of the fit of `s` at the point c (NaN when under-determined).
inline void finish_tangents(const TangentSums& s, const float* c, const NormalOptions& o, float* out) {
  out[0] = out[1] = out[2] = kNaN;
  if (s.N < float(std::max(3, o.min_points))) return;
  // rows 1 and 2 of the adjugate of M = [[N, Su, Sv], [Su, Suu, Suv], [Sv, Suv, Svv]]
  const float c00 = s.Suu * s.Svv - s.Suv * s.Suv, c01 = s.Sv * s.Suv - s.Su * s.Svv,
              c02 = s.Su * s.Suv - s.Sv * s.Suu;
  const float det = s.N * c00 + s.Su * c01 + s.Sv * c02;
  if (!(det > 0.5f)) return;  // an integer; 0 when the pixels are collinear
  const float c11 = s.N * s.Svv - s.Sv * s.Sv, c12 = s.Su * s.Sv - s.N * s.Suv, c22 = s.N * s.Suu - s.Su * s.Su;
  float a[3], b[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = c01 * s.sc[k] + c11 * s.su[k] + c12 * s.sv[k];
    b[k] = c02 * s.sc[k] + c12 * s.su[k] + c22 * s.sv[k];
  }
  store_normal_f(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0], c,
                 out);
}

/// Masked least-squares tangents at an edge pixel: fits p = p0 + a du + b dv to the points of
/// the window of side `side` within depth_change_factor * z of the centre, n = a x b (float:
/// the coordinates are relative to the centre, so they are small).
void explicit_tangents(const Cloud& cloud, int v, int u, int side, const NormalOptions& o, float* out) {
  const float* c = cloud.ptr(v, u);
  const float t = JumpThreshold(o)(c[2]);
  const int r = side / 2;
  TangentSums s;
  // branch-free (the accepted points of an edge window are unpredictable): a rejected or
  // missing point contributes zeros
  for (int dvi = -r; dvi <= r; ++dvi) {
    const int vv = v + dvi;
    if (vv < 0 || vv >= cloud.rows()) continue;
    const float dv = float(dvi);
    for (int dui = -r; dui <= r; ++dui) {
      const int uu = u + dui;
      if (uu < 0 || uu >= cloud.cols()) continue;
      const float* q = cloud.ptr(vv, uu);
      const bool in = std::abs(q[2] - c[2]) <= t;  // also false for a missing (NaN) point
      const float m = in ? 1.f : 0.f;
      const float du = float(dui);
      const float mu = m * du, mv = m * dv;
      s.N += m, s.Su += mu, s.Sv += mv, s.Suu += mu * du, s.Suv += mu * dv, s.Svv += mv * dv;
      for (int k = 0; k < 3; ++k) {
        const float x = in ? q[k] - c[k] : 0.f;
        s.sc[k] += x, s.su[k] += du * x, s.sv[k] += dv * x;
      }
    }
  }
  finish_tangents(s, c, o, out);
}

/// explicit_tangents of 5 x 5 windows inside the image, for the pixels `us` of row v, kLanes
/// pixels at a time: each lane adds the same terms in the same order as explicit_tangents (the
/// same normals), the lanes side by side (vectorized). Stereo frames send ~7% of their pixels
/// here (20,000 a VGA frame), where one at a time they took 45% of the fast method's time.
void explicit_tangents_5x5(const Cloud& cloud, int v, const int* us, int count, const NormalOptions& o,
                           NormalMap& out) {
  constexpr int kLanes = 8, r = 2;
  const JumpThreshold jt(o);
  for (int first = 0; first < count; first += kLanes) {
    const int n = std::min(kLanes, count - first);
    int col[kLanes];
    float cx[kLanes], cy[kLanes], cz[kLanes], t[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      col[l] = us[first + (l < n ? l : 0)];  // (spare lanes repeat the first pixel)
      const float* c = cloud.ptr(v, col[l]);
      cx[l] = c[0], cy[l] = c[1], cz[l] = c[2], t[l] = jt(c[2]);
    }
    float N[kLanes] = {}, Su[kLanes] = {}, Sv[kLanes] = {}, Suu[kLanes] = {}, Suv[kLanes] = {}, Svv[kLanes] = {};
    float sc[3][kLanes] = {}, su[3][kLanes] = {}, sv[3][kLanes] = {};
    for (int dvi = -r; dvi <= r; ++dvi) {
      const float* row = cloud.ptr(v + dvi, 0);
      const float dv = float(dvi);
      for (int dui = -r; dui <= r; ++dui) {
        const float du = float(dui);
        float qx[kLanes], qy[kLanes], qz[kLanes];
        for (int l = 0; l < kLanes; ++l) {
          const float* q = row + 3 * (col[l] + dui);
          qx[l] = q[0], qy[l] = q[1], qz[l] = q[2];
        }
        for (int l = 0; l < kLanes; ++l) {
          const bool in = std::abs(qz[l] - cz[l]) <= t[l];
          const float m = in ? 1.f : 0.f;
          const float mu = m * du, mv = m * dv;
          N[l] += m, Su[l] += mu, Sv[l] += mv, Suu[l] += mu * du, Suv[l] += mu * dv, Svv[l] += mv * dv;
          const float x = in ? qx[l] - cx[l] : 0.f, y = in ? qy[l] - cy[l] : 0.f, z = in ? qz[l] - cz[l] : 0.f;
          sc[0][l] += x, su[0][l] += du * x, sv[0][l] += dv * x;
          sc[1][l] += y, su[1][l] += du * y, sv[1][l] += dv * y;
          sc[2][l] += z, su[2][l] += du * z, sv[2][l] += dv * z;
        }
      }
    }
    for (int l = 0; l < n; ++l) {
      TangentSums s;
      s.N = N[l], s.Su = Su[l], s.Sv = Sv[l], s.Suu = Suu[l], s.Suv = Suv[l], s.Svv = Svv[l];
      for (int k = 0; k < 3; ++k) s.sc[k] = sc[k][l], s.su[k] = su[k][l], s.sv[k] = sv[k][l];
      finish_tangents(s, cloud.ptr(v, col[l]), o, out.ptr(v, col[l]));
    }
  }
}

/// PCA of the accepted points of an edge pixel's window.
void explicit_covariance(const Cloud& cloud, int v, int u, int side, const NormalOptions& o,
                         float* out) {
  double s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  const int n = for_each_near(cloud, v, u, side, JumpThreshold(o),
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

/// Bad-pixel flags, one byte per pixel: 1 for a missing point (z not a positive finite number)
/// or a point with a valid 4-neighbour further than factor * z in depth (either side of a depth
/// jump). A window without bad pixels holds only valid points and never crosses a jump (a
/// window that spans a jump holds an adjacent pair across it, and both are flagged). Written
/// branch-free so that the rows vectorize.
/// The flags of rows [ya, yb) into `flags` ((yb - ya) * W bytes); `zbuf` is scratch.
void bad_rows(const Cloud& cloud, JumpThreshold jt, int ya, int yb, std::vector<float>& zbuf,
              std::uint8_t* flags) {
  const int H = cloud.rows(), W = cloud.cols();
  // z of rows ya-1 .. yb (clamped), NaN where missing
  const int za = std::max(0, ya - 1), zb = std::min(H, yb + 1);
  zbuf.resize(std::size_t(zb - za) * W);
  for (int y = za; y < zb; ++y) {
    const float* p = cloud.ptr(y, 0);
    float* z = zbuf.data() + std::size_t(y - za) * W;
    for (int u = 0; u < W; ++u) {
      const float zz = p[3 * u + 2];
      z[u] = (zz > 0.f && zz < INFINITY) ? zz : kNaN;
    }
  }
  for (int v = ya; v < yb; ++v) {
    const float* z = zbuf.data() + std::size_t(v - za) * W;
    const float* zu = v > 0 ? z - W : z;  // no neighbour outside the image
    const float* zd = v + 1 < H ? z + W : z;
    std::uint8_t* e = flags + std::size_t(v - ya) * W;
    // |a - b| > t is false when a neighbour is missing (NaN): missing neighbours do not count
    const float f = jt.factor, inv = jt.inv_noise_depth;
    for (int u = 1; u + 1 < W; ++u) {
      // jt(z) spelled out with selects and integer ors, so that the loop vectorizes
      const float zc = z[u], q = zc * inv;
      const float t = f * zc * (q > 1.f ? q : 1.f);
      const int bad = (zc > 0.f ? 0 : 1) | int(std::fabs(z[u - 1] - zc) > t) | int(std::fabs(z[u + 1] - zc) > t) |
                      int(std::fabs(zu[u] - zc) > t) | int(std::fabs(zd[u] - zc) > t);
      e[u] = std::uint8_t(bad);
    }
    for (int u : {0, W - 1}) {
      const float t = jt(z[u]);
      const int l = std::max(u - 1, 0), rr = std::min(u + 1, W - 1);
      const bool bad = !(z[u] > 0.f) | (std::abs(z[l] - z[u]) > t) | (std::abs(z[rr] - z[u]) > t) |
                       (std::abs(zu[u] - z[u]) > t) | (std::abs(zd[u] - z[u]) > t);
      e[u] = bad ? 1 : 0;
    }
  }
}

/// The fast method. Per row: vertical box and ramp sums of x, y, z over the window's rows, then
/// horizontal ramp and box sums give t_u = sum du * p and t_v = sum dv * p, n = t_u x t_v, all in
/// float over contiguous arrays (vectorized). A pixel whose window holds an edge pixel (or
/// reaches past the border) is handled alone by explicit_tangents.
/// kR > 0: the window radius as a compile-time constant (unrolled, vectorized inner loops);
/// kR = 0: any radius, read from the options.
template <int kR>
void fast_normals_r(const Cloud& cloud, const NormalOptions& o, NormalMap& out) {
  const int H = cloud.rows(), W = cloud.cols();
  const int r = kR > 0 ? kR : o.window / 2;
  const JumpThreshold jt(o);
  const int block = 32;
  const int blocks = (H + block - 1) / block;
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks, 1), [&](const tbb::blocked_range<int>& br) {
    std::vector<float> soa;                    // rows ya..yb: x, y, z planes, 0 where invalid
    std::vector<float> vs(6 * std::size_t(W));  // Bx By Bz Rx Ry Rz
    std::vector<float> nn(3 * std::size_t(W));  // unnormalised normals
    std::vector<std::uint16_t> cv(W), cnt(W), cv3(W), cnt3(W);
    std::vector<float> zbuf;
    std::vector<std::uint8_t> bad;  // bad-pixel flags of rows ya..yb
    std::vector<int> batched;       // a row's pixels for explicit_tangents_5x5
    for (int b = br.begin(); b < br.end(); ++b) {
      const int v0 = b * block, v1 = std::min(H, v0 + block);
      const int ya = std::max(0, v0 - r), yb = std::min(H, v1 + r);
      soa.resize(std::size_t(yb - ya) * 3 * W);
      bad.resize(std::size_t(yb - ya) * W);
      bad_rows(cloud, jt, ya, yb, zbuf, bad.data());
      auto edge_row = [&](int y) { return bad.data() + std::size_t(y - ya) * W; };
      for (int y = ya; y < yb; ++y) {
        const float* row = cloud.ptr(y, 0);
        const std::uint8_t* e = edge_row(y);
        float* X = soa.data() + std::size_t(y - ya) * 3 * W;
        float* Y = X + W;
        float* Z = Y + W;
        for (int u = 0; u < W; ++u) {
          // bad pixels may be invalid; no window that is summed holds one, so 0 is safe
          const bool ok = !e[u];
          X[u] = ok ? row[3 * u] : 0.f;
          Y[u] = ok ? row[3 * u + 1] : 0.f;
          Z[u] = ok ? row[3 * u + 2] : 0.f;
        }
      }
      auto plane = [&](int y, int c) { return soa.data() + (std::size_t(y - ya) * 3 + c) * W; };
      for (int v = v0; v < v1; ++v) {
        float* nrow = out.ptr(v, 0);
        const float* prow = cloud.ptr(v, 0);
        const bool batch_5x5 = std::min(o.window, 5) == 5 && v >= 2 && v + 2 < H;
        batched.clear();
        const bool rows_inside = v - r >= 0 && v + r < H;
        if (rows_inside) {
          for (int c = 0; c < 3; ++c) {
            float* B = vs.data() + std::size_t(c) * W;
            float* R = vs.data() + std::size_t(3 + c) * W;
            const float* P0 = plane(v, c);
            for (int u = 0; u < W; ++u) B[u] = P0[u], R[u] = 0.f;
            for (int k = 1; k <= r; ++k) {
              const float* Pp = plane(v + k, c);
              const float* Pm = plane(v - k, c);
              const float fk = float(k);
              for (int u = 0; u < W; ++u) {
                B[u] += Pp[u] + Pm[u];
                R[u] += fk * (Pp[u] - Pm[u]);
              }
            }
          }
          // edge pixels in the window: vertical then horizontal counts
          const std::uint8_t* e0 = edge_row(v);
          for (int u = 0; u < W; ++u) cv[u] = e0[u];
          for (int k = 1; k <= r; ++k) {
            const std::uint8_t* ep = edge_row(v + k);
            const std::uint8_t* em = edge_row(v - k);
            for (int u = 0; u < W; ++u) cv[u] = std::uint16_t(cv[u] + ep[u] + em[u]);
          }
          for (int u = r; u + r < W; ++u) {
            std::uint16_t s = cv[u];
            for (int k = 1; k <= r; ++k) s = std::uint16_t(s + cv[u + k] + cv[u - k]);
            cnt[u] = s;
          }
          for (int u = 0; u < r; ++u) cnt[u] = cnt[W - 1 - u] = 1;  // window past the border
          // the same over 3 x 3 (the fallback of pixels near an edge)
          {
            const std::uint8_t* ep = edge_row(v + 1);
            const std::uint8_t* em = edge_row(v - 1);
            for (int u = 0; u < W; ++u) cv3[u] = std::uint16_t(e0[u] + ep[u] + em[u]);
            for (int u = 1; u + 1 < W; ++u) cnt3[u] = std::uint16_t(cv3[u - 1] + cv3[u] + cv3[u + 1]);
            cnt3[0] = cnt3[W - 1] = 1;
          }
          // t_u = sum du * B (horizontal ramp), t_v = sum R (horizontal box); n = t_u x t_v
          const float* Bx = vs.data();
          const float* By = Bx + W;
          const float* Bz = By + W;
          const float* Rx = Bz + W;
          const float* Ry = Rx + W;
          const float* Rz = Ry + W;
          float* NX = nn.data();
          float* NY = NX + W;
          float* NZ = NY + W;
          for (int u = r; u + r < W; ++u) {
            float ax = 0, ay = 0, az = 0, bx = Rx[u], by = Ry[u], bz = Rz[u];
            for (int k = 1; k <= r; ++k) {
              const float fk = float(k);
              ax += fk * (Bx[u + k] - Bx[u - k]);
              ay += fk * (By[u + k] - By[u - k]);
              az += fk * (Bz[u + k] - Bz[u - k]);
              bx += Rx[u + k] + Rx[u - k];
              by += Ry[u + k] + Ry[u - k];
              bz += Rz[u + k] + Rz[u - k];
            }
            NX[u] = ay * bz - az * by;
            NY[u] = az * bx - ax * bz;
            NZ[u] = ax * by - ay * bx;
          }
          // normalise and turn towards the camera (branch-free; 0/0 gives NaN, kept as NaN)
          for (int u = r; u + r < W; ++u) {
            const float* p = prow + 3 * u;
            const float nx = NX[u], ny = NY[u], nz = NZ[u];
            float s = 1.f / std::sqrt(nx * nx + ny * ny + nz * nz);
            s = (nx * p[0] + ny * p[1] + nz * p[2] > 0.f) ? -s : s;
            NX[u] = nx * s, NY[u] = ny * s, NZ[u] = nz * s;
          }
        }
        for (int u = 0; u < W; ++u) {
          const float* p = prow + 3 * u;
          float* n = nrow + 3 * u;
          if (rows_inside && cnt[u] == 0) {
            const float nx = nn[u], ny = nn[W + u], nz = nn[2 * W + u];
            const bool ok = std::isfinite(nx) && std::isfinite(ny) && std::isfinite(nz);
            n[0] = ok ? nx : kNaN, n[1] = ok ? ny : kNaN, n[2] = ok ? nz : kNaN;
          } else if (rows_inside && r > 1 && cnt3[u] == 0) {
            // 3 x 3 tangents from the same planes (no edge pixel among the nine)
            float a[3], bb[3];
            for (int c = 0; c < 3; ++c) {
              const float* Pm = plane(v - 1, c);
              const float* P0 = plane(v, c);
              const float* Pp = plane(v + 1, c);
              a[c] = (Pm[u + 1] - Pm[u - 1]) + (P0[u + 1] - P0[u - 1]) + (Pp[u + 1] - Pp[u - 1]);
              bb[c] = (Pp[u - 1] - Pm[u - 1]) + (Pp[u] - Pm[u]) + (Pp[u + 1] - Pm[u + 1]);
            }
            store_normal_f(a[1] * bb[2] - a[2] * bb[1], a[2] * bb[0] - a[0] * bb[2],
                         a[0] * bb[1] - a[1] * bb[0], p, n);
          } else if (valid_point(p)) {
            if (batch_5x5 && u >= 2 && u + 2 < W)
              batched.push_back(u);  // (below, side by side)
            else
              explicit_tangents(cloud, v, u, std::min(o.window, 5), o, n);
          } else {
            n[0] = n[1] = n[2] = kNaN;
          }
        }
        explicit_tangents_5x5(cloud, v, batched.data(), int(batched.size()), o, out);
      }
    }
  });
}

void fast_normals(const Cloud& cloud, const NormalOptions& o, NormalMap& out) {
  switch (o.window / 2) {
    case 1: return fast_normals_r<1>(cloud, o, out);
    case 2: return fast_normals_r<2>(cloud, o, out);
    case 3: return fast_normals_r<3>(cloud, o, out);
    case 4: return fast_normals_r<4>(cloud, o, out);
    default: return fast_normals_r<0>(cloud, o, out);
  }
}

// ---- covariance: integral images of first and second moments ------------------------------

void covariance_normals(const Cloud& cloud, const NormalOptions& o, NormalMap& out) {
  const int H = cloud.rows(), W = cloud.cols();
  const int smax = o.adaptive_window ? 2 * o.window + 1 : o.window;
  const int rmax = smax / 2;
  // Like PCL's integral-image normals, missing points only leave the sums (a count channel
  // divides them out); windows shrink at depth jumps only.
  const auto dist = edge_distance(cloud, JumpThreshold(o), std::min(rmax + 1, 255), false);
  const int block = std::max(32, 4 * rmax);
  const int blocks = (H + block - 1) / block;
  constexpr int C = 10;  // n x y z xx xy xz yy yz zz
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
        double run[C] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
        for (int u = 0; u < W; ++u) {
          const float* p = row + 3 * u;
          if (valid_point(p)) {
            const double x = p[0], yy = p[1], z = p[2];
            run[0] += 1, run[1] += x, run[2] += yy, run[3] += z;
            run[4] += x * x, run[5] += x * yy, run[6] += x * z;
            run[7] += yy * yy, run[8] += yy * z, run[9] += z * z;
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
          if (r < 1 || (r < 2 && side > 3)) {  // a 3 x 3 (or no) window left: the depth-tested one is better
            explicit_covariance(cloud, v, u, std::min(side, 7), o, n);
            continue;
          }
          const double* t0 = ii.data() + std::size_t(v - r - ya) * stride;
          const double* t1 = ii.data() + std::size_t(v + r + 1 - ya) * stride;
          const double *a = t0 + (u - r) * C, *bb = t0 + (u + r + 1) * C;
          const double *c = t1 + (u - r) * C, *dd = t1 + (u + r + 1) * C;
          double s[C];
          for (int k = 0; k < C; ++k) s[k] = dd[k] - c[k] - bb[k] + a[k];
          if (s[0] < std::max(3, o.min_points)) {
            n[0] = n[1] = n[2] = kNaN;
            continue;
          }
          const double in = 1.0 / s[0];
          const double mx = s[1] * in, my = s[2] * in, mz = s[3] * in;
          double e[3];
          if (smallest_eigenvector(s[4] * in - mx * mx, s[5] * in - mx * my, s[6] * in - mx * mz,
                                   s[7] * in - my * my, s[8] * in - my * mz,
                                   s[9] * in - mz * mz, e))
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
  if (!(o.noise_depth > 0))
    throw InputError("normals: noise_depth must be > 0, got " + std::to_string(o.noise_depth));
  if (!(o.depth_change_factor > 0))
    throw InputError("normals: depth_change_factor must be > 0, got " +
                     std::to_string(o.depth_change_factor));
  if (o.adaptive_window && !(o.reference_depth > 0))
    throw InputError("normals: reference_depth must be > 0, got " +
                     std::to_string(o.reference_depth));
  if (cloud.empty()) return NormalMap(cloud.rows(), cloud.cols(), kNaN);
  // not filled: both methods write every pixel (a normal or NaN)
  NormalMap out(cloud.rows(), cloud.cols(),
                std::shared_ptr<float[]>(new float[std::size_t(cloud.rows()) * cloud.cols() * 3]));
  if (o.method == NormalMethod::Fast)
    fast_normals(cloud, o, out);
  else
    covariance_normals(cloud, o, out);
  return out;
}

}  // namespace mereo::extension
