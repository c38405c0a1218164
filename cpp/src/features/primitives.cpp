// RANSAC detection of the shape table's classes in organized frames (see primitives.hpp).
#include "mereo/features/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/random.hpp"
#include "features/fit.hpp"
#include "features/pixels.hpp"
#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/features/handle.hpp"

namespace mereo::features {
namespace detail {

Pixels::Pixels(const Cloud& c, const NormalMap& n, const DetectOptions& opt) : cloud(c), normals(n), o(opt) {
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

Pixels::Pixels(const Pixels& parent, const DetectOptions& opt)
    : cloud(parent.cloud), normals(parent.normals), o(opt), H(parent.H), W(parent.W), focal(parent.focal),
      free(parent.free) {
  cos_dev = std::cos(o.normal_deviation_deg * kDeg);
}

std::vector<int> Pixels::component(const Segment& s, int seed, int step, const std::uint8_t* mask, std::size_t cap) const {
  std::vector<int> out;
  const int sv = (seed / W) / step * step, su = (seed % W) / step * step;
  const int start = sv * W + su;
  if (!free[start] || (mask && !mask[start])) return out;
  const int sign = orientation(s, start);
  if (!fits(s, start, sign)) return out;
  // visited cells on the grid, per thread: the many small components of a search do not each
  // clear a frame-sized array
  const int gw = (W + step - 1) / step, gh = (H + step - 1) / step;
  thread_local Stamps seen;
  seen.clear(std::size_t(gw) * gh);
  std::vector<int> queue{start};
  seen.insert(std::size_t((sv / step) * gw + su / step));
  s.visit([&](const auto& g) {  // (the class dispatched once, not per pixel)
    for (std::size_t head = 0; head < queue.size() && out.size() < cap; ++head) {
      const int i = queue[head];
      out.push_back(i);
      const int v = i / W, u = i % W;
      const int nb[4][2] = {{v - step, u}, {v + step, u}, {v, u - step}, {v, u + step}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= H || q[1] < 0 || q[1] >= W) continue;
        if (!seen.insert(std::size_t((q[0] / step) * gw + q[1] / step))) continue;
        const int j = q[0] * W + q[1];
        if (free[j] && (!mask || mask[j]) && fits_shape(g, j, sign)) queue.push_back(j);
      }
    }
  });
  return out;
}

void sort_pixels(std::vector<int>& pix, int n) {
  // a large segment (a table: 100,000 pixels) through one pass over per-pixel counts instead of
  // a comparison sort; counts, not flags, so that a repeated pixel stays repeated as sort keeps it
  if (pix.size() < std::size_t(n) / 32) {
    std::sort(pix.begin(), pix.end());
    return;
  }
  thread_local std::vector<std::uint16_t> count;
  count.assign(std::size_t(n), 0);
  for (int i : pix) ++count[std::size_t(i)];
  pix.clear();
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < count[std::size_t(i)]; ++k) pix.push_back(i);
}

void describe(const Pixels& f, Segment& s, std::vector<int> pix, const ColorImage* color) {
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(pix.size());
  for (int i : pix) pts.push_back(f.p(i));
  set_extent(s, pts);
  if (s.solid()) {
    int in = 0;
    for (int i : pix) in += f.orientation(s, i) < 0;
    s.inward = 2 * in > int(pix.size());
  }
  s.visit([](auto& g) { g.canonical(); });  // e.g. a plane's normal towards the camera
  sort_pixels(pix, f.H * f.W);  // (kept sorted: overlaps are binary searches)
  s.inliers = pix.size();
  s.pixels = std::move(pix);
  set_color(s, color);
}

void set_color(Segment& s, const ColorImage* color) {
  if (!color || color->empty() || s.pixels.empty()) return;
  Eigen::Vector3f col = Eigen::Vector3f::Zero();
  for (int i : s.pixels)
    col += Eigen::Vector3f(color->data()[3 * i], color->data()[3 * i + 1], color->data()[3 * i + 2]) / 255.f;
  s.mean_color = col / float(s.pixels.size());
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

}  // namespace detail

namespace {

using detail::Candidate;
using detail::Pixels;

constexpr int kMaxSample = 8;  // the largest minimal set of the shape table

bool wanted(const DetectOptions& o, PrimitiveClass c) {
  return std::find(o.classes.begin(), o.classes.end(), c) != o.classes.end();
}

/// A candidate of class c from the minimal set (p, n) (nullopt when degenerate).
std::optional<Segment> from_sample(PrimitiveClass c, const Eigen::Vector3d* p, const Eigen::Vector3d* n,
                                   const shapes::Limits& limits) {
  return std::visit(
      [&](const auto& proto) -> std::optional<Segment> {
        using S = std::decay_t<decltype(proto)>;
        if (auto g = S::from_sample(p, n, limits)) return Segment(Geometry(std::move(*g)));
        return std::nullopt;
      },
      c.make());
}

bool plausible(const Segment& s, const shapes::Limits& limits) {
  return s.visit([&](const auto& g) { return g.plausible(limits); });
}

/// One round of candidates from `count` seeds drawn with per-task generators seeded by
/// (seed, round, task): the result depends on the seed only, not on the threads.
std::vector<Candidate> draw(const Pixels& f, const std::vector<int>& pool, int round, int count,
                            const std::vector<PrimitiveClass>& classes, const shapes::Limits& limits,
                            const std::uint8_t* mask) {
  std::vector<std::vector<Candidate>> per(count);
  // thin parts (a handle's tube) alone: their points are drawn from a smaller neighbourhood
  bool all_thin = !classes.empty();
  for (PrimitiveClass c : classes) all_thin = all_thin && c.thin();
  tbb::parallel_for(0, count, [&](int t) {
    ::mereo::detail::TaskRandom rng(std::uint64_t(f.o.seed), std::uint64_t(round), std::uint64_t(t));
    const int seed = pool[std::size_t(rng.below(pool.size()))];
    if (!f.free[seed]) return;
    const double radius = all_thin ? std::min(f.o.sample_radius, 0.02) : f.o.sample_radius;
    const int rpx = std::max(3, int(radius * f.focal / f.p(seed).z()));
    auto neighbour = [&]() -> int {
      for (int tries = 0; tries < 16; ++tries) {
        const int v = seed / f.W + rng.below(2 * rpx + 1) - rpx, u = seed % f.W + rng.below(2 * rpx + 1) - rpx;
        if (v < 0 || v >= f.H || u < 0 || u >= f.W) continue;
        const int j = v * f.W + u;
        if (j != seed && f.free[j] && (!mask || mask[j])) return j;
      }
      return -1;
    };
    for (PrimitiveClass c : classes) {
      const int k = c.sample_size();
      if (k < 1 || k > kMaxSample) continue;
      Eigen::Vector3d P[kMaxSample], N[kMaxSample];
      P[0] = f.p(seed), N[0] = f.n(seed);
      bool ok = true;
      for (int m = 1; m < k && ok; ++m) {
        const int j = neighbour();
        ok = j >= 0;
        if (ok) P[m] = f.p(j), N[m] = f.n(j);
      }
      if (!ok) continue;
      const auto s = from_sample(c, P, N, limits);
      if (!s || !plausible(*s, limits)) continue;
      // quick local score: how many of 24 random neighbours fit (given up once too few can)
      int hits = 0;
      const int need = c.thin() ? 5 : 8, sign = f.orientation(*s, seed);
      s->visit([&](const auto& g) {
        for (int m = 0; m < 24 && hits + 24 - m >= need; ++m) {
          const int j = neighbour();
          hits += j >= 0 && f.fits_shape(g, j, sign);
        }
      });
      if (hits < need) continue;
      per[t].push_back({*s, seed, double(hits)});
    }
  });
  std::vector<Candidate> out;
  for (auto& v : per)
    for (auto& c : v) out.push_back(std::move(c));
  return out;
}

/// Least-squares refit of s to the points of `pix`: curved classes (cylinders, spheres) to the
/// unfiltered points (DetectOptions::unfiltered), along the rays (fit_along_rays); others to the
/// cloud's points by geometric distance.
Segment measure(const Pixels& f, const Segment& s, const std::vector<int>& pix) {
  const bool curved = s.curved();
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
  if (const auto* sphere = s.get_if<shapes::Sphere>()) {
    // A narrow band of a sphere and of a cylinder of the same radius differ by less than the
    // noise (a plate's rim). The cylinder is the answer when the normals nearly span one plane
    // (the smallest eigenvalue of their scatter under 5% of the largest; measured on the
    // synthetic scenes: plates' rims 0.017-0.021, bowls 0.23-0.34) and it holds as many pixels.
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (int i : pix) M += f.n(i) * f.n(i).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M);
    if (es.eigenvalues()(0) < 0.05 * es.eigenvalues()(2)) {  // plates 0.02, bowls 0.2-0.35
      Segment c = s;
      shapes::Cylinder cyl;
      cyl.point = sphere->center, cyl.axis = es.eigenvectors().col(0), cyl.radius = sphere->radius;
      c.shape = cyl;
      c = measure(f, c, pix);
      auto cpix = f.component(c, seed, 1, mask);
      if (cpix.size() >= pix.size()) s = c, pix = std::move(cpix);
    }
  }
  detail::describe(f, s, std::move(pix), color);
  return s;
}

/// A segment of a general class that departs too little from the special one it generalizes
/// (a cone of too little taper) is taken for the special class when that is wanted.
/// A segment of a class that a wanted class generalizes (a cylinder, and cones are wanted: a
/// cylinder is a cone of no taper) is tried as that class: refitted from it on the same pixels,
/// it replaces the segment when it holds nearly as many pixels (kRefinePixels) with a residual
/// under kRefineResidual of the segment's. One side of a tapered cup is nearly a cylinder with
/// its axis leaning by the taper, so the gain is small but systematic: residual ratios on the
/// tapered cups of seeds 1100-1123 were 0.82-0.95, on upright cylinders 0.988-1.0 (a thousand
/// points make a 4% drop far more than noise). A class may also ask for a least departure from
/// the special one (Refines' min_departure: a cone's taper; upright cylinders fitted as cones
/// took 0.2-1.8 degrees there, the cups 3.9-9.7; real ones seen in part up to 4.1: Cone::min_departure).
constexpr double kRefineResidual = 0.96, kRefinePixels = 0.98;
Segment refine(const Pixels& f, Segment s, int seed, const std::vector<PrimitiveClass>& classes,
               const shapes::Limits& limits, const ColorImage* color, const std::uint8_t* mask) {
  if (s.pixels.empty()) return s;
  // the other way: a general shape barely departing from its special class, when that is wanted
  s = s.visit([&](const auto& g) -> Segment {
    using G = std::decay_t<decltype(g)>;
    if constexpr (shapes::has_refines<G>::value) {
      const PrimitiveClass special = PrimitiveClass::of<typename G::Refines>();
      if (g.departure() >= G::min_departure ||
          std::find(classes.begin(), classes.end(), special) == classes.end())
        return s;
      Segment t = s;
      t.shape = g.simplified();
      t = measure(f, t, s.pixels);
      auto pix = f.component(t, seed, 1, mask);
      if (pix.size() < 6 || !plausible(t, limits)) return s;
      detail::describe(f, t, std::move(pix), color);
      return t;
    }
    return s;
  });
  for (PrimitiveClass c : classes)
    std::visit(
        [&](const auto& proto) {
          using G = std::decay_t<decltype(proto)>;
          if constexpr (shapes::has_refines<G>::value) {
            const auto* special = s.get_if<typename G::Refines>();
            if (!special) return;
            Segment g = s;
            g.shape = G::refined_from(*special);
            g = measure(f, g, s.pixels);
            g.visit([](auto& x) { x.canonical(); });  // (a cone that narrows along the cylinder's axis)
            if (!plausible(g, limits)) return;
            auto pix = f.component(g, seed, 1, mask);
            if (pix.size() < kRefinePixels * s.pixels.size() || !(g.residual < kRefineResidual * s.residual) ||
                g.template as<G>().departure() < G::min_departure)
              return;
            g = measure(f, g, pix);
            g.visit([](auto& x) { x.canonical(); });
            pix = f.component(g, seed, 1, mask);
            if (pix.size() < kRefinePixels * s.pixels.size() || !plausible(g, limits)) return;
            detail::describe(f, g, std::move(pix), color);
            s = std::move(g);
          }
        },
        c.make());
  return s;
}

/// The detect-refine-remove loop over the pixels of `mask` (or all), for `classes`.
std::vector<Segment> search(Pixels& f, const std::vector<PrimitiveClass>& classes, const std::uint8_t* mask,
                            int min_support_other, int min_support_thin, double min_r, double max_r, int max_count,
                            const ColorImage* color) {
  const shapes::Limits limits = f.limits(min_r, max_r);
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
    auto cands = draw(f, pool, round, f.o.candidates_per_iteration, classes, limits, mask);
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
    const int need = c.s.cls().thin() ? min_support_thin : min_support_other;
    if (c.score < need) break;
    Segment s = refine(f, finish(f, c.s, c.seed, color, mask), c.seed, classes, limits, color, mask);
    if (s.inliers < std::size_t(need) || !plausible(s, limits)) {
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
  if (!o.unfiltered.empty() && !o.unfiltered.same_size(cloud))
    throw InputError("detect_primitives: the unfiltered points and the cloud differ in size");
  if (!(o.epsilon > 0) || o.min_support < 1 || o.min_support_torus < 1 || o.score_step < 1 ||
      o.candidates_per_iteration < 1 || o.max_iterations < 0 || !(o.min_radius > 0) || o.max_radius <= o.min_radius ||
      !(o.min_minor_radius > 0) || o.max_minor_radius <= o.min_minor_radius)
    throw InputError("detect_primitives: an option is out of range (epsilon, supports, steps and radii must be positive, "
                     "max > min)");
}

}  // namespace

double surface_distance(const Segment& s, const Eigen::Vector3d& x) { return std::abs(s.signed_distance(x)); }

Segment refit(const Segment& s, const std::vector<Eigen::Vector3d>& points, bool along_rays) {
  return detail::refit_points(s, points, along_rays ? detail::Residual::AlongRay : detail::Residual::Geometric);
}

SearchRegion region_near(const Segment& segment, double margin) {
  SearchRegion r;
  r.ball_center = segment.origin();
  r.ball_radius = segment.extent() + margin;
  if (segment.is<shapes::Cylinder>()) r.attached_to = segment;
  return r;
}

namespace {

/// A segment found bottom-up that may be a piece of the handle of `body` (HandleOptions::
/// piece_in_reach): not a plane, and not an outer wall (a neighbouring body: a bottle in a pack).
bool piece_of_handle(const Pixels& f, const Segment& body_segment, const Segment& s, const HandleOptions& h) {
  const auto& body = body_segment.as<shapes::Cylinder>();
  if (s.get_if<shapes::Plane>() || s.get_if<shapes::Torus>() || (s.get_if<shapes::Cylinder>() && !s.inward) ||
      s.pixels.empty() || 2 * s.pixels.size() > body_segment.pixels.size())
    return false;
  std::size_t in = 0;
  for (int i : s.pixels) in += h.in_reach(body, f.p(i), 0.5 * f.eps(f.p(i).z()));
  return double(in) >= h.piece_in_reach * double(s.pixels.size());
}

/// find_primitive on a frame already prepared (its taken pixels are not searched). The region's
/// pixels are listed once: for a ball, only the image rectangle that can hold it is scanned (the
/// rectangle of the attached segment's pixels grown by the ball's size in pixels).
std::vector<Segment> find_in(const Pixels& f, PrimitiveClass cls, const SearchRegion& region, const DetectOptions& o,
                             const ColorImage* color, int max_count) {
  Pixels::Box scan{0, 0, f.W - 1, f.H - 1};
  if (region.ball_radius > 0 && region.attached_to && !region.attached_to->pixels.empty()) {
    const Segment& a = *region.attached_to;
    double zmin = INFINITY;
    for (int i : a.pixels) zmin = std::min(zmin, f.p(i).z());
    scan = f.grown(f.box_of(a.pixels),
                   int(std::ceil(region.ball_radius * f.focal / std::max(0.1, zmin - region.ball_radius))));
  }
  std::vector<std::uint8_t> excluded;
  if (!region.exclude.empty()) {
    excluded.assign(std::size_t(f.H) * f.W, 0);
    for (const Segment* s : region.exclude)
      for (int i : s->pixels) excluded[i] = 1;
  }
  std::vector<int> pixels;
  for (int v = scan.v0; v <= scan.v1; ++v)
    for (int u = scan.u0; u <= scan.u1; ++u) {
      const int i = v * f.W + u;
      if (!f.free[i] || (!region.mask.empty() && !region.mask.data()[i]) || (!excluded.empty() && excluded[i])) continue;
      if (region.ball_radius > 0 && (f.p(i) - region.ball_center).norm() > region.ball_radius) continue;
      pixels.push_back(i);
    }
  const double min_r = region.min_radius > 0 ? region.min_radius : o.min_radius;
  const double max_r = region.max_radius > 0 ? region.max_radius : (cls.thin() ? o.max_major_radius : o.max_radius);
  DetectOptions local = o;
  if (region.min_minor_radius > 0) local.min_minor_radius = region.min_minor_radius;
  if (region.max_minor_radius > 0) local.max_minor_radius = region.max_minor_radius;
  local.max_iterations = std::min(o.max_iterations, 8);
  // a handle's tube is about as thick as the normals' window: its normals are poor, so the
  // attached search accepts a wider deviation (the geometric fit does not use them), the visible
  // side of a noisy tube of a few millimetres reads thinner than it is, and a handle is thin
  // (mugs' are 3-10 mm): a fat torus next to a body is something else
  const bool handle = cls == PrimitiveClass::of<shapes::Torus>() && region.attached_to;
  if (handle) {
    const HandleOptions& h = o.handle;
    local.normal_deviation_deg = std::max(o.normal_deviation_deg, h.normal_deviation_factor * o.normal_deviation_deg);
    if (region.min_minor_radius <= 0) local.min_minor_radius = h.min_minor_radius;
    if (region.max_minor_radius <= 0) local.max_minor_radius = std::min(o.max_minor_radius, h.max_minor_radius);
  }
  Pixels g(f, local);
  if (handle)
    return detail::search_handles(g, *region.attached_to, pixels, o.min_support_torus, max_count, color,
                                  g.limits(min_r, max_r));
  std::vector<std::uint8_t> mask(std::size_t(f.H) * f.W, 0);
  for (int i : pixels) mask[i] = 1;
  return search(g, {cls}, mask.data(), std::max(1, o.min_support / 4), o.min_support_torus, min_r, max_r, max_count,
                color);
}

/// What the end of an axial body facing the camera shows (Segment::end_closed, end_open): the
/// valid pixels near the body's image whose rays cross that end's disc (within 0.85 of its
/// radius, clear of the rim) and whose points lie inside the body's radius. A point within
/// [-kBelow, kAbove] of the end plane is on a lid (the visible extent often stops short of a
/// lid's rim, where depth is missing: hence the wider band above); one deeper is inside an open
/// vessel. Points outside the radius are something else, in front or behind, and not counted.
/// A lid covers its disc, so a point counts as on it only within kCore of the radius from the
/// axis: an open vessel's rim, the top of its inner wall and, with stereo depth, the front rim's
/// fattened edge lie at that band's height too, but near the radius (stereo seed 5010: an open
/// mug's end read 285 lid and 112 inside pixels, 3 and 112 so).
/// On the renderer (seeds 20-39 and varied 7000-7019, both depth models) open mugs show at least
/// 0.86 of their end open (0.52 when the lid band counted to the radius), jars, cans and bottles at
/// most 0.3 but for about a tenth of them on the stereo model (its fattened edges lift the visible
/// extent above the lid); a level taken from the points instead (their upper decile) made bottles
/// open (the neck above the shoulder).
void look_at_end(const Pixels& f, Segment& s) {
  constexpr double kBelow = 0.01, kAbove = 0.02, kDisc = 0.85, kMinCos = 0.1, kCore = 0.7;
  Eigen::Vector3d point, axis;
  double height = 0, r_lo = 0, r_hi = 0;  // the radii at the -axis and +axis ends
  if (const auto* c = s.get_if<shapes::Cylinder>()) {
    point = c->point, axis = c->axis.normalized(), height = c->height, r_lo = r_hi = c->radius;
  } else if (const auto* k = s.get_if<shapes::Cone>()) {
    point = k->point, axis = k->axis.normalized(), height = k->height;
    r_lo = k->radius_at(-height / 2), r_hi = k->radius_at(height / 2);
  } else {
    return;
  }
  if (s.inward || s.pixels.empty()) return;
  // the end facing the camera (at the origin), not seen edge-on
  Eigen::Vector3d n = axis, end = point + axis * height / 2;
  double r_end = r_hi;
  if (-n.dot(end) < 0) n = -axis, end = point - axis * height / 2, r_end = r_lo;
  if (!(r_end > 0) || -n.dot(end) < kMinCos * end.norm()) return;
  // the window: the segment's pixel box grown by its larger side each way (the cap's image lies
  // next to the body's)
  const Pixels::Box body = f.box_of(s.pixels);
  const Pixels::Box w = f.grown(body, std::max(body.u1 - body.u0, body.v1 - body.v0) + 1);
  for (int v = w.v0; v <= w.v1; ++v)
    for (int u = w.u0; u <= w.u1; ++u) {
      const float* q = f.cloud.ptr(v, u);
      if (!valid_point(q)) continue;
      const Eigen::Vector3d x(q[0], q[1], q[2]);
      const double along_ray = n.dot(x);
      if (along_ray >= 0) continue;  // the ray runs away from the end plane
      const Eigen::Vector3d crossing = x * (n.dot(end) / along_ray);
      if ((crossing - end).norm() > kDisc * r_end) continue;
      const Eigen::Vector3d rel = x - end;
      const double h = n.dot(rel);
      const double radial = (rel - n * h).norm();
      if (radial > r_end) continue;  // (a cone's radius differs little over kBelow)
      if (h > kAbove) continue;
      if (h < -kBelow) s.end_open += 1;
      else if (radial < kCore * r_end) s.end_closed += 1;
    }
}

}  // namespace

namespace {

/// A least-squares fit of per-pixel values by a model whose first column is a constant, and
/// whether the other columns explain the values beyond their noise: the F statistic of those
/// columns against the constant alone. The F statistic counts the pixels as fewer independent
/// samples where the residuals are correlated across neighbouring pixels (a stereo matcher's
/// window makes patches of depth err together): the variance of the residuals' means over
/// kBlock x kBlock pixel blocks against that of independent pixels gives how many pixels err as one.
struct PixelFit {
  static constexpr int kBlock = 8;
  std::vector<double> rows, values;  // row-major design matrix (first column 1), one value per row
  std::vector<int> blocks;
  int cols;
  explicit PixelFit(int columns) : cols(columns) {}
  void add(const double* row, double value, int pixel, int width) {
    rows.insert(rows.end(), row, row + cols), values.push_back(value);
    blocks.push_back((pixel / width) / kBlock * ((width + kBlock - 1) / kBlock) + (pixel % width) / kBlock);
  }
  std::size_t size() const { return values.size(); }
  /// Solves; the coefficients (empty when singular) and the F statistic of columns 1.. beyond the constant.
  std::pair<Eigen::VectorXd, double> solve() const {
    const Eigen::Index m = Eigen::Index(values.size());
    if (m <= cols) return {};
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(rows.data(), m, cols);
    const Eigen::Map<const Eigen::VectorXd> b(values.data(), m);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.transpose() * A);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return {};
    Eigen::VectorXd coef = ldlt.solve(A.transpose() * b);
    const Eigen::VectorXd r = b - A * coef;
    const double rss = r.squaredNorm(), rss0 = (b.array() - b.mean()).square().sum();
    if (!(rss > 0)) return {};
    std::unordered_map<int, std::pair<double, int>> sums;
    for (Eigen::Index i = 0; i < m; ++i) {
      auto& s = sums[blocks[std::size_t(i)]];
      s.first += r[i], s.second += 1;
    }
    double block_ss = 0;  // sum over blocks of count * mean^2: one residual variance per block when independent
    for (const auto& [key, s] : sums) block_ss += s.first * s.first / s.second;
    const double together = std::max(1.0, block_ss / (double(sums.size()) * rss / double(m)));
    const double F = (rss0 - rss) / (cols - 1) / (rss / double(m - cols)) / together;
    return {std::move(coef), F};
  }
};

/// The tori among `others` that could hold a handle of the axial segment s.
std::vector<const Segment*> tori_near(const Segment& s, const std::vector<Segment>& others) {
  std::vector<const Segment*> tori;
  for (const auto& o : others)
    if (o.is<shapes::Torus>() && o.surface_distance(s.origin()) < s.extent() + o.extent()) tori.push_back(&o);
  return tori;
}

/// Pixels within kHandleClearance of a torus in `tori` (a handle's roots).
constexpr double kHandleClearance = 0.015;
bool by_handle(const Eigen::Vector3d& x, const std::vector<const Segment*>& tori) {
  return std::any_of(tori.begin(), tori.end(), [&](const Segment* t) { return t->surface_distance(x) < kHandleClearance; });
}

}  // namespace

namespace detail {

/// How much an axial body's surface bends along its axis, as its normals show (Segment::bend).
/// On a cylinder or a cone the normals' component along the axis is constant; on a tube bent by
/// a curvature k it changes along the axis by k cos(theta) per metre, theta being the azimuth
/// around the axis from the side the tube bends to; on a blob (a barrel) it changes alike on all
/// sides. So the component is fitted by least squares as c + t (g + a cos(theta) + b sin(theta))
/// over the pixels between the 10th and 90th percentile of their position t on the axis (a rim's
/// or a foot's smoothed normals at the ends would tilt it), and the bend is the RMS, over the
/// pixels, of the fitted slope g + a cos(theta) + b sin(theta) (1 / m).
/// Kept only when the three slope terms explain the component beyond its noise (PixelFit's F
/// statistic of at least kMinF), else 0.
/// Pixels next to a torus among `others` are left out: a handle's roots turn the wall's normals
/// up and down on one side, as a bend would.
/// Rendered frames, seeds 6000-6049 (cylinders and cones fitted by the default graph): with the
/// Kinect-like model, true bodies' slopes are below 1.1 / m and 18 of 27 cylinders on bananas
/// are kept bending by more than 2.5 / m; with the stereo model, 21 of 80 mug bodies slope by more
/// than 2.5 / m, all of them with an F below 10.
void measure_bend(const Pixels& f, Segment& s, const std::vector<Segment>& others) {
  constexpr double kMinF = 10.0;
  const auto axis = s.direction();
  if (!axis || !(s.is<shapes::Cylinder>() || s.is<shapes::Cone>()) || s.pixels.size() < 20) return;
  const Eigen::Vector3d a = axis->normalized(), c = s.origin();
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  struct Sample {
    double t, n, cos, sin;  // position on the axis, the normal's component along it, azimuth
    int pixel;
  };
  std::vector<Sample> xs;
  xs.reserve(s.pixels.size());
  const auto tori = tori_near(s, others);
  for (int i : s.pixels) {
    const Eigen::Vector3d n = f.n(i), q = f.p(i) - c;
    if (by_handle(f.p(i), tori)) continue;
    const double x = e1.dot(q), y = e2.dot(q), r = std::hypot(x, y);
    if (n.allFinite() && r > 0) xs.push_back({a.dot(q), a.dot(n), x / r, y / r, i});
  }
  if (xs.size() < 20) return;
  // the 10th to 90th percentile of the positions on the axis
  std::sort(xs.begin(), xs.end(), [](const Sample& u, const Sample& v) { return u.t < v.t; });
  const std::size_t cut = xs.size() / 10;
  xs.erase(xs.end() - std::ptrdiff_t(cut), xs.end());
  xs.erase(xs.begin(), xs.begin() + std::ptrdiff_t(cut));
  PixelFit fit(4);
  for (const auto& x : xs) {
    const double row[4] = {1, x.t, x.t * x.cos, x.t * x.sin};
    fit.add(row, x.n, x.pixel, f.W);
  }
  const auto [coef, F] = fit.solve();
  if (coef.size() == 0 || F < kMinF) return;
  double slope2 = 0;
  for (const auto& x : xs) slope2 += std::pow(coef[1] + coef[2] * x.cos + coef[3] * x.sin, 2);
  s.bend = std::sqrt(slope2 / double(xs.size()));
}

/// How far an axial body's cross-section is from a circle (Segment::out_of_round). The signed
/// distance d of each pixel's unfiltered point from the fitted surface is fitted by least squares
/// as c + sum over k = 2..4 of (a_k cos(k theta) + b_k sin(k theta)), theta being the azimuth
/// around the axis: on a round body d is noise whatever theta, on a rounded box it dips on the
/// flat faces and rises on the rounded edges between them (the first harmonic is a shifted axis,
/// which the fit already took out). The value is the RMS over the pixels of the fitted pattern,
/// over the mean distance from the axis; 0 unless the pattern explains d beyond its noise
/// (PixelFit's F of at least kMinF). Pixels next to a torus among `others` are left out.
/// Rendered frames, seeds 5000-5049 and 7000-7049 (cylinders fitted by the default graph, arcs of
/// at least 100 degrees): with the Kinect-like model, no F of 450 container bodies reaches 20
/// (one reaches 14: a jar whose cylinder took some of its lid), and 9 of 15 rounded boxes do,
/// with patterns of 0.045-0.074 of the radius; with the stereo model no F reaches 20.
void measure_out_of_round(const Pixels& f, Segment& s, const std::vector<Segment>& others) {
  constexpr double kMinF = 20.0;
  constexpr int kHarmonics = 3;  // k = 2, 3, 4
  const auto axis = s.direction();
  if (!axis || !(s.is<shapes::Cylinder>() || s.is<shapes::Cone>()) || s.inward || s.pixels.size() < 50) return;
  const Eigen::Vector3d a = axis->normalized(), c = s.origin();
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const auto tori = tori_near(s, others);
  PixelFit fit(1 + 2 * kHarmonics);
  double radius = 0;
  for (int i : s.pixels) {
    const Eigen::Vector3d x = f.raw(i), q = x - c;
    if (!x.allFinite() || by_handle(x, tori)) continue;
    const double theta = std::atan2(e2.dot(q), e1.dot(q));
    double row[1 + 2 * kHarmonics] = {1};
    for (int k = 0; k < kHarmonics; ++k) row[1 + 2 * k] = std::cos((k + 2) * theta), row[2 + 2 * k] = std::sin((k + 2) * theta);
    fit.add(row, s.signed_distance(x), i, f.W);
    radius += (q - a * a.dot(q)).norm();
  }
  if (fit.size() < 50) return;
  const auto [coef, F] = fit.solve();
  if (coef.size() == 0 || F < kMinF) return;
  const Eigen::Index m = Eigen::Index(fit.size()), cols = fit.cols;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(fit.rows.data(), m, cols);
  const Eigen::VectorXd pattern = A.rightCols(cols - 1) * coef.tail(cols - 1);
  s.out_of_round = std::sqrt(pattern.squaredNorm() / double(m)) / (radius / double(m));
}

}  // namespace detail

std::vector<Segment> detect_primitives(const Cloud& cloud, const NormalMap& normals, const DetectOptions& o,
                                       const ColorImage* color) {
  check(cloud, normals, o);
  Pixels f(cloud, normals, o);
  const HandleOptions& h = o.handle;
  // with the handle search on, tori are looked for top-down only (next to the bodies): a
  // bottom-up torus through a few noisy pixels is seldom anything
  const PrimitiveClass torus = PrimitiveClass::of<shapes::Torus>();
  const bool top_down_tori = h.search_near_cylinders && wanted(o, torus);
  std::vector<PrimitiveClass> bottom_up;  // in the table's order
  for (PrimitiveClass c : primitive_classes())
    if (wanted(o, c) && c.sample_size() > 0 && !(c == torus && top_down_tori)) bottom_up.push_back(c);
  auto out = search(f, bottom_up, nullptr, o.min_support, o.min_support_torus, o.min_radius, o.max_radius,
                    o.max_primitives, color);
  if (o.upright_bodies && wanted(o, PrimitiveClass::of<shapes::Cylinder>())) {
    detail::hold_upright(f, o.support, out, o.min_radius, o.max_radius);
    detail::search_upright(f, o.support, out, o.min_support, o.min_radius, o.max_radius, o.max_primitives - int(out.size()),
                           color);
    detail::outer_walls(f, o.support, out, o.min_radius, o.max_radius, color);
  }
  // the pixels each upright body grew by (offered to the handle search: a handle's roots)
  std::vector<std::vector<int>> grown(out.size());
  if (o.upright_bodies && wanted(o, PrimitiveClass::of<shapes::Cylinder>()))
    grown = detail::grow_upright(f, o.support, out, o.min_radius, o.max_radius, color);
  if (top_down_tori) {
    // the top-down rule: a handle next to every cylinder that could be a body (the segments
    // found so far keep their pixels: they are taken in f)
    // A wide handle's side is nearly a cylinder, and the bottom-up pass may have taken it as a
    // small one: the pixels of small cylinders next to the body are offered to the handle
    // search too, and a torus that takes most of such a cylinder replaces it.
    const std::size_t n = out.size();
    std::vector<bool> dropped(n, false);
    auto outer_cylinder = [&](std::size_t j) -> const shapes::Cylinder* {
      const auto* c = out[j].get_if<shapes::Cylinder>();
      return c && !out[j].inward ? c : nullptr;
    };
    for (std::size_t k = 0; k < n && int(out.size()) < o.max_primitives; ++k) {
      const shapes::Cylinder* body = outer_cylinder(k);
      // an upright tapered body is searched as the cylinder of its widest radius (a tapered
      // mug; or a mug's wall that stereo noise and the handle's roots lean into a taper)
      const std::optional<Segment> tapered = body ? std::nullopt : detail::upright_cone_as_cylinder(o.support, out[k]);
      if (tapered) body = &tapered->as<shapes::Cylinder>();
      const Segment& body_segment = tapered ? *tapered : out[k];
      if (!body || body->radius < h.body_min_radius || body->radius > h.body_max_radius) continue;
      const SearchRegion region = region_near(body_segment, h.region_margin);
      std::vector<std::size_t> offered;
      for (std::size_t j = 0; j < n; ++j) {
        if (j == k || dropped[j]) continue;
        const shapes::Cylinder* small = outer_cylinder(j);
        const bool small_side = small && small->radius < h.small_cylinder_ratio * body->radius &&
                                (small->point - region.ball_center).norm() < region.ball_radius;
        if (small_side || piece_of_handle(f, body_segment, out[j], h)) {
          offered.push_back(j);
          for (int i : out[j].pixels) f.free[i] = 1;
        }
      }
      for (int i : grown[k]) f.free[i] = 1;
      auto found = find_in(f, torus, region, o, color, 1);
      // a patch of the body's own wall, or the wider rest of a tapered one, is no handle
      // (handle.hpp: wall_patch, tapered_wall)
      const auto points_of = [&](const std::vector<int>& pixels) {
        std::vector<Eigen::Vector3d> pts;
        pts.reserve(pixels.size());
        for (int i : pixels) pts.push_back(f.p(i));
        return pts;
      };
      const auto eps = [&](double z) { return f.eps(z); };
      found.erase(std::remove_if(found.begin(), found.end(),
                                 [&](const Segment& t) {
                                   const auto pts = points_of(t.pixels);
                                   return wall_patch(*body, t, pts, eps) ||
                                          tapered_wall(*body, points_of(out[k].pixels), pts, eps);
                                 }),
                  found.end());
      // where the depth shows no handle (none, or rings no handle has: HandleOptions::beside),
      // the colour image is asked
      const auto no_handle = [&] {
        return std::none_of(found.begin(), found.end(), [&](const Segment& t) { return h.beside(*body, t); });
      };
      if (no_handle() && h.from_colour)
        if (auto t = detail::colour_handle(f, body_segment, color, h.colour_max_turn_deg)) found.push_back(std::move(*t));
      if (no_handle() && h.from_edges)
        if (auto t = detail::edge_handle(f, body_segment, color)) found.push_back(std::move(*t));
      for (std::size_t j : offered) {
        std::size_t shared = 0;
        for (const auto& t : found)
          for (int i : t.pixels) shared += std::binary_search(out[j].pixels.begin(), out[j].pixels.end(), i);
        if (2 * shared > out[j].pixels.size()) dropped[j] = true;
        for (int i : out[j].pixels) f.free[i] = 0;
      }
      for (int i : grown[k]) f.free[i] = 0;
      if (!grown[k].empty() && !found.empty()) {  // the handle keeps what the body grew into
        std::vector<int> handle_pixels;
        for (const auto& t : found) handle_pixels.insert(handle_pixels.end(), t.pixels.begin(), t.pixels.end());
        std::sort(handle_pixels.begin(), handle_pixels.end());
        std::vector<int> pix;
        std::set_difference(out[k].pixels.begin(), out[k].pixels.end(), handle_pixels.begin(), handle_pixels.end(),
                            std::back_inserter(pix));
        if (pix.size() < out[k].pixels.size()) detail::describe(f, out[k], std::move(pix), color);
      }
      // a body with a handle is a mug's: a tapered one is held as its upright cylinder
      if (tapered && !found.empty()) detail::hold_as_cylinder(f, o.support, out[k], o.min_radius, o.max_radius, color);
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
  // (each segment on its own thread: they write only their own ends, bend and out-of-round, and
  // read only the tori of the others)
  tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t k) {
    look_at_end(f, out[k]), detail::measure_bend(f, out[k], out), detail::measure_out_of_round(f, out[k], out);
  });
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
