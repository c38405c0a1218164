// RANSAC detection of planes, cylinders, spheres and tori in organized frames (see primitives.hpp).
#include "mereo/features/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <random>
#include <string>

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
  Eigen::Vector3d p(int i) const {
    const float* q = cloud.data() + 3 * std::size_t(i);
    return Eigen::Vector3d(q[0], q[1], q[2]);
  }
  Eigen::Vector3d n(int i) const { return Eigen::Vector3d(normals.data()[3 * i], normals.data()[3 * i + 1], normals.data()[3 * i + 2]); }
  double eps(double z) const { return o.epsilon * std::max(0.3, 1 + o.epsilon_growth * (z * z - 1)); }
  /// Pixel i fits segment s: distance within eps(z) and normal within the deviation.
  bool fits(const Segment& s, int i) const {
    const Eigen::Vector3d x = p(i);
    Eigen::Vector3d sn;
    const double d = signed_distance(s, x, &sn);
    return std::abs(d) <= eps(x.z()) && std::abs(sn.dot(n(i))) >= cos_dev;
  }
  /// The 4-connected component of free pixels that fit s, from `seed`, on a grid of `step`
  /// pixels (seed snapped to it); `mask` (optional) restricts it. Capped at `cap` cells.
  std::vector<int> component(const Segment& s, int seed, int step, const std::uint8_t* mask = nullptr,
                             std::size_t cap = SIZE_MAX) const {
    std::vector<int> out;
    const int sv = (seed / W) / step * step, su = (seed % W) / step * step;
    const int start = sv * W + su;
    if (!free[start] || (mask && !mask[start]) || !fits(s, start)) return out;
    std::vector<std::uint8_t> seen;
    // visited cells, hashed densely on the grid
    const int gw = (W + step - 1) / step, gh = (H + step - 1) / step;
    seen.assign(std::size_t(gw) * gh, 0);
    std::deque<int> queue{start};
    seen[(sv / step) * gw + su / step] = 1;
    while (!queue.empty() && out.size() < cap) {
      const int i = queue.front();
      queue.pop_front();
      out.push_back(i);
      const int v = i / W, u = i % W;
      const int nb[4][2] = {{v - step, u}, {v + step, u}, {v, u - step}, {v, u + step}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= H || q[1] < 0 || q[1] >= W) continue;
        std::uint8_t& sn = seen[(q[0] / step) * gw + q[1] / step];
        if (sn) continue;
        sn = 1;
        const int j = q[0] * W + q[1];
        if (free[j] && (!mask || mask[j]) && fits(s, j)) queue.push_back(j);
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

/// One round of candidates from `count` seeds drawn with per-task generators seeded by
/// (seed, round, task): the result depends on the seed only, not on the threads.
/// A handle hypothesis from a seed pixel next to a body: the ring plane holds the body's axis and
/// the radial direction to the seed; three pixels of the plane's slab, moved by -r along their
/// normals (r on a grid over the tube range), give the ring as the circle through them.
std::optional<Segment> handle_from(const Pixels& f, const Segment& body, int seed, std::mt19937_64& rng,
                                   const std::vector<int>& slab_pool) {
  const Eigen::Vector3d a = body.axis.normalized();
  const Eigen::Vector3d q = f.p(seed) - body.point;
  Eigen::Vector3d u = q - a * a.dot(q);
  if (u.norm() < 1e-6) return std::nullopt;
  u.normalize();
  const Eigen::Vector3d n = a.cross(u).normalized();  // the ring plane's normal
  // pixels near that plane (the seed's own slab)
  // pixels near that plane, outside the body's wall and within its height
  std::vector<int> near;
  for (int j : slab_pool) {
    const Eigen::Vector3d x = f.p(j) - body.point;
    const double along = a.dot(x), radial = (x - a * along).norm();
    if (std::abs(n.dot(x)) < 0.012 && radial > body.radius + f.eps(f.p(j).z()) &&
        std::abs(along) < 0.5 * body.height + 0.01)
      near.push_back(j);
  }
  if (near.size() < 3) return std::nullopt;
  // the seed and two pixels of the slab within 3 cm of it; the tube radius from a handle's range
  const Eigen::Vector3d p0 = f.p(seed);
  std::vector<int> close;
  for (int j : near)
    if (j != seed && (f.p(j) - p0).norm() < 0.03) close.push_back(j);
  if (close.size() < 2) return std::nullopt;
  const double rmax = std::min(f.o.max_minor_radius, 0.01);
  const double r = f.o.min_minor_radius + (rmax - f.o.min_minor_radius) * std::uniform_real_distribution<double>(0, 1)(rng);
  Eigen::Vector3d t[3];
  for (int k = 0; k < 3; ++k) {
    const int j = k == 0 ? seed : close[rng() % close.size()];
    Eigen::Vector3d pn = f.n(j);
    if (pn.dot(f.p(j)) > 0) pn = -pn;
    const Eigen::Vector3d c = f.p(j) - r * pn;            // the tube centre, if the normal is right
    t[k] = c - n * n.dot(c - body.point);                 // in the ring plane
  }
  const Eigen::Vector3d ab = t[1] - t[0], ac = t[2] - t[0], nn = ab.cross(ac);
  const double l2 = nn.squaredNorm();
  if (l2 < 1e-12) return std::nullopt;
  Segment s;
  s.cls = PrimitiveClass::Torus;
  s.point = t[0] + (ac.squaredNorm() * nn.cross(ab) + ab.squaredNorm() * ac.cross(nn)) / (2 * l2);
  s.axis = n;
  s.radius = (t[0] - s.point).norm();
  s.minor_radius = r;
  return s;
}

std::vector<Candidate> draw(const Pixels& f, const std::vector<int>& pool, int round, int count,
                            const std::vector<PrimitiveClass>& classes, double min_r, double max_r,
                            const std::uint8_t* mask, const Segment* body = nullptr) {
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
      } else if (c == PrimitiveClass::Torus && body) {
        s = handle_from(f, *body, seed, rng, pool);
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
      for (int k = 0; k < 24; ++k) {
        const int j = neighbour();
        hits += j >= 0 && f.fits(*s, j);
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

/// The segment of a candidate: refit to its full-resolution component twice, with extent,
/// colour and pixels. Empty pixels when it does not hold.
Segment finish(const Pixels& f, Segment s, int seed, const ColorImage* color, const std::uint8_t* mask) {
  for (int round = 0; round < 2; ++round) {
    const auto pix = f.component(s, seed, 1, mask);
    if (pix.size() < 6) return Segment{};
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(pix.size());
    for (int i : pix) pts.push_back(f.p(i));
    s = detail::refit_points(s, pts);
  }
  auto pix = f.component(s, seed, 1, mask);
  if (pix.size() < 6) return Segment{};
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(pix.size());
  Eigen::Vector3f col = Eigen::Vector3f::Zero();
  for (int i : pix) {
    pts.push_back(f.p(i));
    if (color && !color->empty())
      col += Eigen::Vector3f(color->data()[3 * i], color->data()[3 * i + 1], color->data()[3 * i + 2]) / 255.f;
  }
  detail::set_extent(s, pts);
  if (s.cls == PrimitiveClass::Plane && s.axis.dot(s.point) > 0) s.axis = -s.axis, s.d = -s.d;  // towards the camera
  s.inliers = pix.size();
  s.pixels = std::move(pix);
  if (color && !color->empty()) {
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
  return s;
}

/// The detect-refine-remove loop over the pixels of `mask` (or all), for `classes`.
std::vector<Segment> search(Pixels& f, const std::vector<PrimitiveClass>& classes, const std::uint8_t* mask,
                            int min_support_other, int min_support_torus, double min_r, double max_r, int max_count,
                            const ColorImage* color, const Segment* body = nullptr) {
  std::vector<Segment> out;
  const int step = std::max(1, f.o.score_step);
  for (int round = 0; round < f.o.max_iterations && int(out.size()) < max_count; ++round) {
    std::vector<int> pool;
    for (int i = 0; i < f.H * f.W; i += 1)
      if (f.free[i] && (!mask || mask[i]) && (i / f.W) % step == 0 && (i % f.W) % step == 0) pool.push_back(i);
    if (pool.size() < 4) break;
    auto cands = draw(f, pool, round, f.o.candidates_per_iteration, classes, min_r, max_r, mask, body);
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

void check(const Cloud& cloud, const NormalMap& normals, const DetectOptions& o) {
  if (!cloud.same_size(normals))
    throw InputError("detect_primitives: cloud " + std::to_string(cloud.cols()) + "x" + std::to_string(cloud.rows()) +
                     " and normals " + std::to_string(normals.cols()) + "x" + std::to_string(normals.rows()) +
                     " differ in size");
  if (!o.roi.empty() && !o.roi.same_size(cloud)) throw InputError("detect_primitives: roi and cloud differ in size");
  if (!(o.epsilon > 0) || o.min_support < 1 || o.min_support_torus < 1 || o.score_step < 1 ||
      o.candidates_per_iteration < 1 || o.max_iterations < 0 || !(o.min_radius > 0) || o.max_radius <= o.min_radius ||
      !(o.min_minor_radius > 0) || o.max_minor_radius <= o.min_minor_radius)
    throw InputError("detect_primitives: an option is out of range (epsilon, supports, steps and radii must be positive, "
                     "max > min)");
}

}  // namespace

double surface_distance(const Segment& s, const Eigen::Vector3d& x) { return std::abs(signed_distance(s, x)); }

Segment refit(const Segment& s, const std::vector<Eigen::Vector3d>& points) { return detail::refit_points(s, points); }

SearchRegion region_near(const Segment& segment, double margin) {
  SearchRegion r;
  r.ball_center = segment.point;
  r.ball_radius = std::hypot(segment.radius, 0.5 * segment.height) + margin;
  if (segment.cls == PrimitiveClass::Cylinder) r.attached_to = segment;
  return r;
}

std::vector<Segment> detect_primitives(const Cloud& cloud, const NormalMap& normals, const DetectOptions& o,
                                       const ColorImage* color) {
  check(cloud, normals, o);
  Pixels f(cloud, normals, o);
  std::vector<PrimitiveClass> bottom_up;
  for (auto c : {PrimitiveClass::Plane, PrimitiveClass::Cylinder, PrimitiveClass::Sphere, PrimitiveClass::Torus})
    if (wanted(o, c)) bottom_up.push_back(c);
  auto out = search(f, bottom_up, nullptr, o.min_support, o.min_support_torus, o.min_radius, o.max_radius,
                    o.max_primitives, color);
  if (o.handles_near_cylinders && wanted(o, PrimitiveClass::Torus)) {
    const std::size_t n = out.size();
    for (std::size_t k = 0; k < n && int(out.size()) < o.max_primitives; ++k) {
      if (out[k].cls != PrimitiveClass::Cylinder) continue;
      SearchRegion r = region_near(out[k], 0.04);
      for (const Segment& other : out) r.exclude.push_back(&other);  // their pixels stay theirs
      auto found = find_primitive(cloud, normals, PrimitiveClass::Torus, r, o, color, 1);
      // pixels already taken by other segments stay theirs
      for (auto& t : found) {
        bool overlaps = false;
        for (int i : t.pixels) overlaps = overlaps || !f.free[i];
        if (overlaps) continue;
        for (int i : t.pixels) f.free[i] = 0;
        out.push_back(std::move(t));
      }
    }
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
  Pixels f(cloud, normals, o);
  std::vector<std::uint8_t> mask(std::size_t(f.H) * f.W, 1);
  for (int i = 0; i < f.H * f.W; ++i) {
    if (!region.mask.empty() && !region.mask.data()[i]) mask[i] = 0;
    if (region.ball_radius > 0 && mask[i] && f.free[i] &&
        (f.p(i) - region.ball_center).norm() > region.ball_radius)
      mask[i] = 0;
  }
  for (const Segment* s : region.exclude)
    for (int i : s->pixels) mask[i] = 0;
  const double min_r = region.min_radius > 0 ? region.min_radius : o.min_radius;
  const double max_r = region.max_radius > 0 ? region.max_radius : (cls == PrimitiveClass::Torus ? o.max_major_radius : o.max_radius);
  DetectOptions local = o;
  if (region.min_minor_radius > 0) local.min_minor_radius = region.min_minor_radius;
  if (region.max_minor_radius > 0) local.max_minor_radius = region.max_minor_radius;
  local.max_iterations = std::min(o.max_iterations, 8);
  Pixels g(cloud, normals, local);
  g.free = f.free;
  const Segment* body = cls == PrimitiveClass::Torus && region.attached_to ? &*region.attached_to : nullptr;
  return search(g, {cls}, mask.data(), std::max(1, o.min_support / 4), o.min_support_torus, min_r, max_r, max_count,
                color, body);
}

}  // namespace mereo::features
