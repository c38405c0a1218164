// RANSAC detection of planes, cylinders, spheres and tori in organized frames (see primitives.hpp).
#include "mereo/features/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unordered_map>

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "features/shapes.hpp"
#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"

namespace mereo::features {
namespace {

using detail::signed_distance;
constexpr double kDeg = M_PI / 180.0;

inline bool finite3(const float* p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// Everything the search reads, built once per call.
struct Pixels {
  const Cloud& cloud;
  const NormalMap& normals;
  const DetectOptions& o;
  int H, W;
  double focal;
  double cos_dev;
  std::vector<std::uint8_t> free;  // usable and not taken by a segment

  Pixels(const Cloud& c, const NormalMap& n, const DetectOptions& opt) : cloud(c), normals(n), o(opt) {
    H = c.rows(), W = c.cols();
    cos_dev = std::cos(o.normal_deviation_deg * kDeg);
    focal = o.focal_px > 0 ? o.focal_px : 0.0;
    if (focal <= 0) {
      try {
        focal = extension::fit_intrinsics(c).fx;
      } catch (const InputError&) {
        focal = 525.0;
      }
    }
    free.assign(std::size_t(H) * W, 0);
    for (int i = 0; i < H * W; ++i) {
      const bool in_roi = o.roi.empty() || o.roi.data()[i];
      free[i] = in_roi && finite3(c.data() + 3 * i) && finite3(n.data() + 3 * i) && c.data()[3 * i + 2] > 0;
    }
  }
  /// The same frame and taken pixels under other options (a model-driven search).
  Pixels(const Pixels& parent, const DetectOptions& opt)
      : cloud(parent.cloud), normals(parent.normals), o(opt), H(parent.H), W(parent.W), focal(parent.focal),
        free(parent.free) {
    cos_dev = std::cos(o.normal_deviation_deg * kDeg);
  }
  Eigen::Vector3d p(int i) const {
    const float* q = cloud.data() + 3 * std::size_t(i);
    return Eigen::Vector3d(q[0], q[1], q[2]);
  }
  /// The unfiltered point of pixel i (DetectOptions::unfiltered) where it has one, else p(i).
  Eigen::Vector3d raw(int i) const {
    if (o.unfiltered.empty()) return p(i);
    const float* q = o.unfiltered.data() + 3 * std::size_t(i);
    return finite3(q) ? Eigen::Vector3d(q[0], q[1], q[2]) : p(i);
  }
  Eigen::Vector3d n(int i) const { return Eigen::Vector3d(normals.data()[3 * i], normals.data()[3 * i + 1], normals.data()[3 * i + 2]); }
  double eps(double z) const { return o.epsilon * std::max(0.3, 1 + o.epsilon_growth * (z * z - 1)); }
  /// +1 when pixel i's normal agrees with the outward normal of s at its closest point, -1 when it
  /// is opposed (a concave side: a mug's inner wall), 0 for planes (normals face the camera).
  int orientation(const Segment& s, int i) const {
    if (s.cls == PrimitiveClass::Plane) return 0;
    Eigen::Vector3d sn;
    signed_distance(s, p(i), &sn);
    return sn.dot(n(i)) >= 0 ? 1 : -1;
  }
  /// Pixel i fits segment s: distance within eps(z) and normal within the deviation, on the
  /// side `sign` (see orientation; 0 = either side). The sign keeps a mug's outer wall and its
  /// visible inner wall, a few millimetres apart but facing opposite ways, in different segments.
  bool fits(const Segment& s, int i, int sign = 0) const {
    const Eigen::Vector3d x = p(i);
    Eigen::Vector3d sn;
    const double d = signed_distance(s, x, &sn);
    const double c = sn.dot(n(i));
    return std::abs(d) <= eps(x.z()) && (sign == 0 ? std::abs(c) : sign * c) >= cos_dev;
  }
  /// Pixel i is within eps(z) of s and its normal is not turned away from the surface (within
  /// 120 degrees of its outward normal): the test for thin parts whose normals are too noisy for
  /// fits(), and whose fitted tube may sit a little in front of or behind the points.
  bool near_facing(const Segment& s, int i) const {
    const Eigen::Vector3d x = p(i);
    Eigen::Vector3d sn;
    const double d = signed_distance(s, x, &sn);
    return std::abs(d) <= eps(x.z()) && sn.dot(n(i)) > -0.5;
  }
  /// The 4-connected component of free pixels that fit s, from `seed`, on a grid of `step`
  /// pixels (seed snapped to it); `mask` (optional) restricts it. Capped at `cap` cells.
  std::vector<int> component(const Segment& s, int seed, int step, const std::uint8_t* mask = nullptr,
                             std::size_t cap = SIZE_MAX) const {
    std::vector<int> out;
    const int sv = (seed / W) / step * step, su = (seed % W) / step * step;
    const int start = sv * W + su;
    if (!free[start] || (mask && !mask[start])) return out;
    const int sign = orientation(s, start);
    if (!fits(s, start, sign)) return out;
    // visited cells on the grid: a per-thread buffer stamped with a generation number, so that
    // the many small components of a search do not each clear a frame-sized array
    const int gw = (W + step - 1) / step, gh = (H + step - 1) / step;
    thread_local std::vector<std::uint32_t> seen;
    thread_local std::uint32_t generation = 0;
    if (seen.size() < std::size_t(gw) * gh) seen.assign(std::size_t(gw) * gh, 0), generation = 0;
    if (++generation == 0) std::fill(seen.begin(), seen.end(), 0), generation = 1;
    std::vector<int> queue{start};
    seen[(sv / step) * gw + su / step] = generation;
    for (std::size_t head = 0; head < queue.size() && out.size() < cap; ++head) {
      const int i = queue[head];
      out.push_back(i);
      const int v = i / W, u = i % W;
      const int nb[4][2] = {{v - step, u}, {v + step, u}, {v, u - step}, {v, u + step}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= H || q[1] < 0 || q[1] >= W) continue;
        std::uint32_t& sn = seen[(q[0] / step) * gw + q[1] / step];
        if (sn == generation) continue;
        sn = generation;
        const int j = q[0] * W + q[1];
        if (free[j] && (!mask || mask[j]) && fits(s, j, sign)) queue.push_back(j);
      }
    }
    return out;
  }
};

bool wanted(const DetectOptions& o, PrimitiveClass c) {
  return std::find(o.classes.begin(), o.classes.end(), c) != o.classes.end();
}

bool plausible(const Segment& s, const DetectOptions& o, double max_radius, double min_radius) {
  switch (s.cls) {
    case PrimitiveClass::Plane: return true;
    case PrimitiveClass::Sphere:
    case PrimitiveClass::Cylinder: return s.radius >= min_radius && s.radius <= max_radius;
    case PrimitiveClass::Torus:
      return s.minor_radius >= o.min_minor_radius && s.minor_radius <= o.max_minor_radius &&
             s.radius > s.minor_radius && s.radius <= o.max_major_radius;
    default: return false;
  }
}

struct Candidate {
  Segment s;
  int seed = -1;
  double score = 0;  // estimated inlier pixels
};

/// Handle hypotheses next to a body (the model-driven search for a mug's handle). A handle is a
/// torus whose ring plane holds the body's axis, outside the wall, within the body's height:
///  1. the usable pixels of `region` between the wall (radius + noise) and 7 cm beyond it, within
///     the body's visible height (less 3 mm: the table's edge pixels at its foot are not a
///     handle), are binned by azimuth about the axis;
///  2. the best azimuth windows (25 deg, at most two that do not overlap) give a ring plane each
///     (through the axis, at the circular mean azimuth of their pixels);
///  3. a torus starting at the window's extent (tube radius 6 mm, ring radius = half its height
///     span, outer edge at its farthest pixel) is refined by Levenberg-Marquardt on the pixels of
///     the window standing off the wall (a geometric fit, detail::refit_handle: the normals of a
///     noisy 1 cm tube are poor): the ring with the tube held, trimmed twice to the points within
///     2 epsilon, then the tube too if it stays plausible.
/// Each plausible torus is a candidate scored by its pixels within epsilon. Deterministic.
std::vector<Candidate> handle_hypotheses(const Pixels& f, const Segment& body, const std::vector<int>& region,
                                         int min_support) {
  const Eigen::Vector3d a = body.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  struct Near {
    int i;
    double theta, rho;
  };
  std::vector<Near> pts;
  for (int i : region) {
    if (!f.free[i]) continue;
    const Eigen::Vector3d x = f.p(i) - body.point;
    const double h = a.dot(x);
    const Eigen::Vector3d radial = x - a * h;
    const double rho = radial.norm();
    if (rho <= body.radius + 0.5 * f.eps(f.p(i).z()) || rho > body.radius + 0.07) continue;
    if (std::abs(h) > 0.5 * body.height - 0.003) continue;  // a handle stays off the table
    pts.push_back({i, std::atan2(radial.dot(e2), radial.dot(e1)), rho});
  }
  std::vector<Candidate> out;
  if (int(pts.size()) < min_support) return out;
  constexpr int kBins = 72, kWindow = 5;  // 5-degree bins, 25-degree windows
  std::vector<int> hist(kBins, 0);
  for (const auto& q : pts) hist[std::min(kBins - 1, int((q.theta + M_PI) / (2 * M_PI) * kBins))]++;
  auto window = [&](int b) {
    int sum = 0;
    for (int k = -kWindow / 2; k <= kWindow / 2; ++k) sum += hist[(b + k + kBins) % kBins];
    return sum;
  };
  std::vector<int> peaks;
  for (int pass = 0; pass < 2; ++pass) {
    int best = -1, best_sum = 0;
    for (int b = 0; b < kBins; ++b) {
      bool clear = true;
      for (int p : peaks) clear = clear && std::min((b - p + kBins) % kBins, (p - b + kBins) % kBins) > kWindow;
      if (clear && window(b) > best_sum) best = b, best_sum = window(b);
    }
    if (best < 0 || best_sum < min_support) break;
    peaks.push_back(best);
  }
  for (int peak : peaks) {
    const double theta0 = (peak + 0.5) / kBins * 2 * M_PI - M_PI;
    std::vector<Eigen::Vector3d> sel;
    double sc = 0, ss = 0;
    for (const auto& q : pts) {
      const double d = std::remainder(q.theta - theta0, 2 * M_PI);
      // the fit starts from the part of the handle that stands off the wall (a finger's width):
      // next to the wall, the wall's own noisy pixels would pull it
      if (std::abs(d) > 15.0 * kDeg || q.rho < body.radius + std::max(0.008, f.eps(f.p(q.i).z()))) continue;
      sel.push_back(f.p(q.i));
      sc += std::cos(q.theta), ss += std::sin(q.theta);
    }
    if (int(sel.size()) < min_support) continue;
    const double theta = std::atan2(ss, sc);
    const Eigen::Vector3d u = std::cos(theta) * e1 + std::sin(theta) * e2;
    double hmin = INFINITY, hmax = -INFINITY, rmax = 0;
    for (const auto& x : sel) {
      const double h = a.dot(x - body.point);
      hmin = std::min(hmin, h), hmax = std::max(hmax, h);
      rmax = std::max(rmax, u.dot(x - body.point));
    }
    Segment t;
    t.cls = PrimitiveClass::Torus;
    t.axis = a.cross(u).normalized();
    t.minor_radius = 0.006;  // (with the ring plane held, 4, 6 and 8 mm starts converge alike)
    t.radius = std::max(0.012, 0.5 * (hmax - hmin) - t.minor_radius);
    t.point = body.point + a * (0.5 * (hmin + hmax)) + u * std::max(body.radius, rmax - t.minor_radius - t.radius);
    // the ring first, with the tube radius held (trimmed twice), then everything if the
    // tube radius stays within the handle's range
    t = detail::refit_handle(body, t, sel, true);
    std::vector<Eigen::Vector3d> kept;
    for (int round = 0; round < 2; ++round) {
      kept.clear();
      for (const auto& x : sel)
        if (std::abs(signed_distance(t, x)) <= 2 * f.eps(x.z())) kept.push_back(x);
      if (int(kept.size()) < min_support) break;
      t = detail::refit_handle(body, t, kept, true);
    }
    if (int(kept.size()) >= min_support) {
      const Segment free_fit = detail::refit_handle(body, t, kept);
      if (plausible(free_fit, f.o, f.o.max_major_radius, 0.0)) t = free_fit;
    }
    if (!plausible(t, f.o, f.o.max_major_radius, 0.0)) continue;
    int score = 0;
    for (const auto& x : sel) score += std::abs(signed_distance(t, x)) <= f.eps(x.z());
    if (score >= min_support) out.push_back({t, -1, double(score)});
  }
  return out;
}

/// One round of candidates from `count` seeds drawn with per-task generators seeded by
/// (seed, round, task): the result depends on the seed only, not on the threads.
std::vector<Candidate> draw(const Pixels& f, const std::vector<int>& pool, int round, int count,
                            const std::vector<PrimitiveClass>& classes, double min_r, double max_r,
                            const std::uint8_t* mask) {
  std::vector<std::vector<Candidate>> per(count);
  tbb::parallel_for(0, count, [&](int t) {
    std::mt19937_64 rng(f.o.seed * 0x9E3779B97F4A7C15ULL + std::uint64_t(round) * 1000003ULL + std::uint64_t(t));
    const int seed = pool[rng() % pool.size()];
    if (!f.free[seed]) return;
    const Eigen::Vector3d p0 = f.p(seed), n0 = f.n(seed);
    // tori (handles) are thin: their points are drawn from a smaller neighbourhood
    const bool only_torus = classes.size() == 1 && classes[0] == PrimitiveClass::Torus;
    const double radius = only_torus ? std::min(f.o.sample_radius, 0.02) : f.o.sample_radius;
    const int rpx = std::max(3, int(radius * f.focal / p0.z()));
    auto neighbour = [&]() -> int {
      for (int tries = 0; tries < 16; ++tries) {
        const int v = seed / f.W + int(rng() % (2 * rpx + 1)) - rpx, u = seed % f.W + int(rng() % (2 * rpx + 1)) - rpx;
        if (v < 0 || v >= f.H || u < 0 || u >= f.W) continue;
        const int j = v * f.W + u;
        if (j != seed && f.free[j] && (!mask || mask[j])) return j;
      }
      return -1;
    };
    for (PrimitiveClass c : classes) {
      std::optional<Segment> s;
      if (c == PrimitiveClass::Plane) {
        s = detail::plane_from(p0, n0);
      } else if (c == PrimitiveClass::Sphere || c == PrimitiveClass::Cylinder) {
        const int j = neighbour();
        if (j < 0) continue;
        s = c == PrimitiveClass::Sphere ? detail::sphere_from(p0, n0, f.p(j), f.n(j))
                                        : detail::cylinder_from(p0, n0, f.p(j), f.n(j));
      } else if (c == PrimitiveClass::Torus) {
        Eigen::Vector3d P[4] = {p0}, N[4] = {n0};
        bool ok = true;
        for (int k = 1; k < 4 && ok; ++k) {
          const int j = neighbour();
          ok = j >= 0;
          if (ok) P[k] = f.p(j), N[k] = f.n(j);
        }
        if (!ok) continue;
        s = detail::torus_from(P, N, f.o.min_minor_radius, f.o.max_minor_radius);
      }
      if (!s || !plausible(*s, f.o, max_r, min_r)) continue;
      // quick local score: how many of 24 random neighbours fit
      int hits = 0;
      const int sign = f.orientation(*s, seed);
      for (int k = 0; k < 24; ++k) {
        const int j = neighbour();
        hits += j >= 0 && f.fits(*s, j, sign);
      }
      if (hits < (c == PrimitiveClass::Torus ? 5 : 8)) continue;
      per[t].push_back({*s, seed, double(hits)});
    }
  });
  std::vector<Candidate> out;
  for (auto& v : per)
    for (auto& c : v) out.push_back(std::move(c));
  return out;
}

/// Sets a segment's pixels, inlier count, visible extent (cylinders), centroid (planes) and mean
/// colour and hue (when `color` is given).
void describe(const Pixels& f, Segment& s, std::vector<int> pix, const ColorImage* color) {
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(pix.size());
  Eigen::Vector3f col = Eigen::Vector3f::Zero();
  for (int i : pix) {
    pts.push_back(f.p(i));
    if (color && !color->empty())
      col += Eigen::Vector3f(color->data()[3 * i], color->data()[3 * i + 1], color->data()[3 * i + 2]) / 255.f;
  }
  detail::set_extent(s, pts);
  if (s.cls != PrimitiveClass::Plane) {
    int in = 0;
    for (int i : pix) in += f.orientation(s, i) < 0;
    s.inward = 2 * in > int(pix.size());
  }
  if (s.cls == PrimitiveClass::Plane && s.axis.dot(s.point) > 0) s.axis = -s.axis, s.d = -s.d;  // towards the camera
  std::sort(pix.begin(), pix.end());  // (kept sorted: overlaps are binary searches)
  s.inliers = pix.size();
  s.pixels = std::move(pix);
  if (color && !color->empty() && s.inliers > 0) {
    s.mean_color = col / float(s.inliers);
    const float r = s.mean_color.x(), g = s.mean_color.y(), b = s.mean_color.z();
    const float mx = std::max({r, g, b}), mn = std::min({r, g, b});
    double h = 0;
    if (mx > mn) {
      if (mx == r) h = 60 * std::fmod((g - b) / (mx - mn), 6.f);
      else if (mx == g) h = 60 * ((b - r) / (mx - mn) + 2);
      else h = 60 * ((r - g) / (mx - mn) + 4);
    }
    s.hue = h < 0 ? h + 360 : h;
  }
}

/// Least-squares refit of s to the points of `pix`: cylinders and spheres to the unfiltered points
/// (DetectOptions::unfiltered), along the rays (fit_along_rays); other classes to the cloud's
/// points by geometric distance.
Segment measure(const Pixels& f, const Segment& s, const std::vector<int>& pix) {
  const bool curved = s.cls == PrimitiveClass::Cylinder || s.cls == PrimitiveClass::Sphere;
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(pix.size());
  for (int i : pix) pts.push_back(curved ? f.raw(i) : f.p(i));
  const bool along = curved && f.o.fit_along_rays;
  return detail::refit_points(s, pts, along ? detail::Residual::AlongRay : detail::Residual::Geometric);
}

/// The segment of a candidate: refit to its full-resolution component twice, with extent,
/// colour and pixels. Empty pixels when it does not hold.
Segment finish(const Pixels& f, Segment s, int seed, const ColorImage* color, const std::uint8_t* mask) {
  for (int round = 0; round < 2; ++round) {
    const auto pix = f.component(s, seed, 1, mask);
    if (pix.size() < 6) return Segment{};
    s = measure(f, s, pix);
  }
  auto pix = f.component(s, seed, 1, mask);
  if (pix.size() < 6) return Segment{};
  if (s.cls == PrimitiveClass::Sphere) {
    // A narrow band of a sphere and of a cylinder of the same radius differ by less than the
    // noise (a plate's rim). The cylinder is the answer when the normals nearly span one plane
    // (the smallest eigenvalue of their scatter under 5% of the largest; measured on the
    // synthetic scenes: plates' rims 0.017-0.021, bowls 0.23-0.34) and it holds as many pixels.
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (int i : pix) M += f.n(i) * f.n(i).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);
    if (es.eigenvalues()(0) < 0.05 * es.eigenvalues()(2)) {  // plates 0.02, bowls 0.2-0.35
      Segment c = s;
      c.cls = PrimitiveClass::Cylinder;
      c.axis = es.eigenvectors().col(0);
      c = measure(f, c, pix);
      auto cpix = f.component(c, seed, 1, mask);
      if (cpix.size() >= pix.size()) s = c, pix = std::move(cpix);
    }
  }
  describe(f, s, std::move(pix), color);
  return s;
}

/// The detect-refine-remove loop over the pixels of `mask` (or all), for `classes`.
std::vector<Segment> search(Pixels& f, const std::vector<PrimitiveClass>& classes, const std::uint8_t* mask,
                            int min_support_other, int min_support_torus, double min_r, double max_r, int max_count,
                            const ColorImage* color) {
  std::vector<Segment> out;
  const int step = std::max(1, f.o.score_step);
  std::vector<int> pool;  // the usable pixels on the grid, shrinking as segments take them
  for (int v = 0; v < f.H; v += step)
    for (int u = 0; u < f.W; u += step) {
      const int i = v * f.W + u;
      if (f.free[i] && (!mask || mask[i])) pool.push_back(i);
    }
  for (int round = 0; round < f.o.max_iterations && int(out.size()) < max_count; ++round) {
    pool.erase(std::remove_if(pool.begin(), pool.end(), [&](int i) { return !f.free[i]; }), pool.end());
    if (pool.size() < 4) break;
    auto cands = draw(f, pool, round, f.o.candidates_per_iteration, classes, min_r, max_r, mask);
    if (cands.empty()) break;
    // the most locally supported candidates get a grid component score (in parallel)
    std::stable_sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    cands.resize(std::min<std::size_t>(cands.size(), 24));
    tbb::parallel_for(std::size_t(0), cands.size(), [&](std::size_t k) {
      cands[k].score = double(f.component(cands[k].s, cands[k].seed, step, mask).size() * step * step);
    });
    // best first; ties broken by the candidate's order (deterministic)
    std::size_t best = 0;
    for (std::size_t k = 1; k < cands.size(); ++k)
      if (cands[k].score > cands[best].score) best = k;
    const Candidate& c = cands[best];
    const int need = c.s.cls == PrimitiveClass::Torus ? min_support_torus : min_support_other;
    if (c.score < need) break;
    Segment s = finish(f, c.s, c.seed, color, mask);
    if (s.inliers < std::size_t(need) || !plausible(s, f.o, max_r, min_r)) {
      // not worth it: take the seed's pixel out of the pool so the loop moves on
      f.free[c.seed] = 0;
      continue;
    }
    for (int i : s.pixels) f.free[i] = 0;
    out.push_back(std::move(s));
  }
  return out;
}

/// The pixels of a handle torus: of the usable pixels in `region`, those within epsilon of it
/// whose normal faces out of the tube (near_facing: a tube of a few millimetres is about as thick
/// as the normals' window, so its normals are too poor for the usual deviation), largest group
/// connected across gaps of one pixel (noise leaves holes in a band a few pixels wide).
std::vector<int> handle_pixels(const Pixels& f, const Segment& t, const std::vector<int>& region) {
  std::vector<int> fit;
  for (int i : region)
    if (f.free[i] && f.near_facing(t, i)) fit.push_back(i);
  // label 8-connected groups among `fit` (a small set: a map from pixel to group)
  std::vector<int> group(fit.size(), -1);
  std::unordered_map<int, int> where;
  for (std::size_t k = 0; k < fit.size(); ++k) where[fit[k]] = int(k);
  int best = -1, best_size = 0, groups = 0;
  for (std::size_t k = 0; k < fit.size(); ++k) {
    if (group[k] >= 0) continue;
    int size = 0;
    std::vector<int> stack{int(k)};
    group[k] = groups;
    while (!stack.empty()) {
      const int m = stack.back();
      stack.pop_back();
      ++size;
      const int v = fit[m] / f.W, u = fit[m] % f.W;
      for (int dv = -2; dv <= 2; ++dv)
        for (int du = -2; du <= 2; ++du) {
          if ((!dv && !du) || v + dv < 0 || v + dv >= f.H || u + du < 0 || u + du >= f.W) continue;
          const auto it = where.find((v + dv) * f.W + u + du);
          if (it != where.end() && group[it->second] < 0) group[it->second] = groups, stack.push_back(it->second);
        }
    }
    if (size > best_size) best = groups, best_size = size;
    ++groups;
  }
  std::vector<int> out;
  for (std::size_t k = 0; k < fit.size(); ++k)
    if (group[k] == best) out.push_back(fit[k]);
  return out;
}

/// The model-driven handle search next to `body` over the pixels `region` (free ones count): the
/// best of handle_hypotheses() by its pixels
/// (handle_pixels), refined twice with the ring plane held through the body's axis; not a handle
/// when the ring would rather turn its plane away from the axis (detail::handle_turn: more than
/// `max_handle_turn_deg`, with a residual under 0.6 of the held one); repeated while another
/// handle has the support (at most `max_count`).
std::vector<Segment> search_handles(Pixels& f, const Segment& body, const std::vector<int>& region, int min_support,
                                    int max_count, const ColorImage* color) {
  std::vector<Segment> out;
  while (int(out.size()) < max_count) {
    const auto cands = handle_hypotheses(f, body, region, min_support);
    Segment best;
    std::vector<int> best_pix;
    for (const Candidate& c : cands) {
      auto pix = handle_pixels(f, c.s, region);
      if (pix.size() > best_pix.size()) best = c.s, best_pix = std::move(pix);
    }
    if (int(best_pix.size()) < min_support) break;
    // refit to the pixels' points: everything if the tube stays plausible, else the ring with
    // the tube held
    auto points_of = [&](const std::vector<int>& pix) {
      std::vector<Eigen::Vector3d> pts;
      for (int i : pix) pts.push_back(f.p(i));
      return pts;
    };
    auto refit_to = [&](const std::vector<Eigen::Vector3d>& pts) {
      return detail::refit_handle_or_hold(body, best, pts,
                                          [&](const Segment& s) { return plausible(s, f.o, f.o.max_major_radius, 0.0); });
    };
    for (int round = 0; round < 2; ++round) {
      best = refit_to(points_of(best_pix));
      best_pix = handle_pixels(f, best, region);
    }
    if (int(best_pix.size()) < min_support || !plausible(best, f.o, f.o.max_major_radius, 0.0)) break;
    const auto pts = points_of(best_pix);
    best = refit_to(pts);  // (the residual of the final pixels)
    // a handle's ring plane holds the body's axis; a ring whose points would rather have it
    // turned away (a ring leaning on a jar) is not one: the search stops there
    if (f.o.max_handle_turn_deg < 90) {
      const auto turn = detail::handle_turn(body, best, pts);
      if (std::abs(turn.turn_deg) > f.o.max_handle_turn_deg && turn.rms_turned < 0.6 * turn.rms_held) break;
    }
    for (int i : best_pix) f.free[i] = 0;
    describe(f, best, std::move(best_pix), color);
    out.push_back(std::move(best));
  }
  return out;
}

void check(const Cloud& cloud, const NormalMap& normals, const DetectOptions& o) {
  if (!cloud.same_size(normals))
    throw InputError("detect_primitives: cloud " + std::to_string(cloud.cols()) + "x" + std::to_string(cloud.rows()) +
                     " and normals " + std::to_string(normals.cols()) + "x" + std::to_string(normals.rows()) +
                     " differ in size");
  if (!o.roi.empty() && !o.roi.same_size(cloud)) throw InputError("detect_primitives: roi and cloud differ in size");
  if (!o.unfiltered.empty() && !o.unfiltered.same_size(cloud))
    throw InputError("detect_primitives: the unfiltered points and the cloud differ in size");
  if (!(o.epsilon > 0) || o.min_support < 1 || o.min_support_torus < 1 || o.score_step < 1 ||
      o.candidates_per_iteration < 1 || o.max_iterations < 0 || !(o.min_radius > 0) || o.max_radius <= o.min_radius ||
      !(o.min_minor_radius > 0) || o.max_minor_radius <= o.min_minor_radius)
    throw InputError("detect_primitives: an option is out of range (epsilon, supports, steps and radii must be positive, "
                     "max > min)");
}

}  // namespace

double surface_distance(const Segment& s, const Eigen::Vector3d& x) { return std::abs(signed_distance(s, x)); }

Segment refit(const Segment& s, const std::vector<Eigen::Vector3d>& points, bool along_rays) {
  return detail::refit_points(s, points, along_rays ? detail::Residual::AlongRay : detail::Residual::Geometric);
}

SearchRegion region_near(const Segment& segment, double margin) {
  SearchRegion r;
  r.ball_center = segment.point;
  r.ball_radius = std::hypot(segment.radius, 0.5 * segment.height) + margin;
  if (segment.cls == PrimitiveClass::Cylinder) r.attached_to = segment;
  return r;
}

namespace {

/// find_primitive on a frame already prepared (its taken pixels are not searched). The region's
/// pixels are listed once: for a ball, only the image rectangle that can hold it is scanned (the
/// rectangle of the attached segment's pixels grown by the ball's size in pixels).
std::vector<Segment> find_in(const Pixels& f, PrimitiveClass cls, const SearchRegion& region, const DetectOptions& o,
                             const ColorImage* color, int max_count) {
  int v0 = 0, v1 = f.H - 1, u0 = 0, u1 = f.W - 1;
  if (region.ball_radius > 0 && region.attached_to && !region.attached_to->pixels.empty()) {
    const Segment& a = *region.attached_to;
    v0 = f.H, v1 = -1, u0 = f.W, u1 = -1;
    double zmin = INFINITY;
    for (int i : a.pixels) {
      v0 = std::min(v0, i / f.W), v1 = std::max(v1, i / f.W), u0 = std::min(u0, i % f.W), u1 = std::max(u1, i % f.W);
      zmin = std::min(zmin, f.p(i).z());
    }
    const int grow = int(std::ceil(region.ball_radius * f.focal / std::max(0.1, zmin - region.ball_radius)));
    v0 = std::max(0, v0 - grow), v1 = std::min(f.H - 1, v1 + grow);
    u0 = std::max(0, u0 - grow), u1 = std::min(f.W - 1, u1 + grow);
  }
  std::vector<std::uint8_t> excluded;
  if (!region.exclude.empty()) {
    excluded.assign(std::size_t(f.H) * f.W, 0);
    for (const Segment* s : region.exclude)
      for (int i : s->pixels) excluded[i] = 1;
  }
  std::vector<int> pixels;
  for (int v = v0; v <= v1; ++v)
    for (int u = u0; u <= u1; ++u) {
      const int i = v * f.W + u;
      if (!f.free[i] || (!region.mask.empty() && !region.mask.data()[i]) || (!excluded.empty() && excluded[i])) continue;
      if (region.ball_radius > 0 && (f.p(i) - region.ball_center).norm() > region.ball_radius) continue;
      pixels.push_back(i);
    }
  const double min_r = region.min_radius > 0 ? region.min_radius : o.min_radius;
  const double max_r = region.max_radius > 0 ? region.max_radius : (cls == PrimitiveClass::Torus ? o.max_major_radius : o.max_radius);
  DetectOptions local = o;
  if (region.min_minor_radius > 0) local.min_minor_radius = region.min_minor_radius;
  if (region.max_minor_radius > 0) local.max_minor_radius = region.max_minor_radius;
  local.max_iterations = std::min(o.max_iterations, 8);
  // a handle's tube is about as thick as the normals' window: its normals are poor, so the
  // attached search accepts twice the usual deviation (the geometric fit does not use them)
  // and the visible side of a noisy tube of a few millimetres reads thinner than it is
  const bool handle = cls == PrimitiveClass::Torus && region.attached_to;
  if (handle) {
    local.normal_deviation_deg = std::max(o.normal_deviation_deg, 2 * o.normal_deviation_deg);
    if (region.min_minor_radius <= 0) local.min_minor_radius = 0.5 * o.min_minor_radius;
    // and a handle is thin (mugs' are 3-10 mm): a fat torus next to a body is something else
    if (region.max_minor_radius <= 0) local.max_minor_radius = std::min(o.max_minor_radius, 0.012);
  }
  Pixels g(f, local);
  if (handle) return search_handles(g, *region.attached_to, pixels, o.min_support_torus, max_count, color);
  std::vector<std::uint8_t> mask(std::size_t(f.H) * f.W, 0);
  for (int i : pixels) mask[i] = 1;
  return search(g, {cls}, mask.data(), std::max(1, o.min_support / 4), o.min_support_torus, min_r, max_r, max_count,
                color);
}

}  // namespace

std::vector<Segment> detect_primitives(const Cloud& cloud, const NormalMap& normals, const DetectOptions& o,
                                       const ColorImage* color) {
  check(cloud, normals, o);
  Pixels f(cloud, normals, o);
  std::vector<PrimitiveClass> bottom_up;
  // with the handle search on, tori are looked for top-down only (next to the bodies): a
  // bottom-up torus through a few noisy pixels is seldom anything
  const bool top_down_tori = o.handles_near_cylinders && wanted(o, PrimitiveClass::Torus);
  for (auto c : {PrimitiveClass::Plane, PrimitiveClass::Cylinder, PrimitiveClass::Sphere, PrimitiveClass::Torus})
    if (wanted(o, c) && !(c == PrimitiveClass::Torus && top_down_tori)) bottom_up.push_back(c);
  auto out = search(f, bottom_up, nullptr, o.min_support, o.min_support_torus, o.min_radius, o.max_radius,
                    o.max_primitives, color);
  if (top_down_tori) {
    // the top-down rule: a handle next to every cylinder that could be a body (the segments
    // found so far keep their pixels: they are taken in f)
    // A wide handle's side is nearly a cylinder, and the bottom-up pass may have taken it as a
    // small one: the pixels of small cylinders next to the body are offered to the handle
    // search too, and a torus that takes most of such a cylinder replaces it.
    const std::size_t n = out.size();
    std::vector<bool> dropped(n, false);
    for (std::size_t k = 0; k < n && int(out.size()) < o.max_primitives; ++k) {
      const Segment& body = out[k];
      if (body.cls != PrimitiveClass::Cylinder || body.inward || body.radius < o.handle_body_min_radius ||
          body.radius > o.handle_body_max_radius)
        continue;
      const SearchRegion region = region_near(body, 0.04);
      std::vector<std::size_t> offered;
      for (std::size_t j = 0; j < n; ++j)
        if (j != k && !dropped[j] && out[j].cls == PrimitiveClass::Cylinder && !out[j].inward &&
            out[j].radius < 0.5 * body.radius && (out[j].point - region.ball_center).norm() < region.ball_radius) {
          offered.push_back(j);
          for (int i : out[j].pixels) f.free[i] = 1;
        }
      auto found = find_in(f, PrimitiveClass::Torus, region, o, color, 1);
      for (std::size_t j : offered) {
        std::size_t shared = 0;
        for (const auto& t : found)
          for (int i : t.pixels) shared += std::binary_search(out[j].pixels.begin(), out[j].pixels.end(), i);
        if (2 * shared > out[j].pixels.size()) dropped[j] = true;
        for (int i : out[j].pixels) f.free[i] = 0;
      }
      for (auto& t : found) {
        for (int i : t.pixels) f.free[i] = 0;
        out.push_back(std::move(t));
      }
    }
    std::vector<Segment> kept;
    for (std::size_t j = 0; j < out.size(); ++j)
      if (j >= n || !dropped[j]) kept.push_back(std::move(out[j]));
    out = std::move(kept);
  }
  std::stable_sort(out.begin(), out.end(), [](const Segment& a, const Segment& b) { return a.inliers > b.inliers; });
  for (std::size_t i = 0; i < out.size(); ++i) out[i].id = int(i);
  return out;
}

std::vector<Segment> find_primitive(const Cloud& cloud, const NormalMap& normals, PrimitiveClass cls,
                                    const SearchRegion& region, const DetectOptions& o, const ColorImage* color,
                                    int max_count) {
  check(cloud, normals, o);
  if (!region.mask.empty() && !region.mask.same_size(cloud))
    throw InputError("find_primitive: the region's mask and the cloud differ in size");
  const Pixels f(cloud, normals, o);
  return find_in(f, cls, region, o, color, max_count);
}

}  // namespace mereo::features
