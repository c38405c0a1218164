// Upright bodies found without normals (features/pixels.hpp: search_upright).
//
// An active-stereo camera's depth at a metre is wavy: errors of ~9 mm correlated over patches of
// ~9 pixels (the matcher's window). Normals over a few pixels then turn by tens of degrees, and the
// bottom-up search, whose minimal sets and scores use them, misses the bodies of cups and cans
// (rendered stereo seeds 6000-6049: no cylinder near 26 of 75 mugs, nearly all beyond 0.9 m). On
// the support plane the axis of a standing body is known, the support's normal, and a body is a
// circle in the plane: fitted to the points of a patch, with the normals used only to tell the
// outer wall from the table and the inner wall, it holds (a fit to the true body pixels with the
// axis held gave radii within 5 mm up to 1.35 m there).
#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Dense>
#include <tbb/parallel_for.h>

#include "core/plane2.hpp"
#include "core/random.hpp"
#include "features/pixels.hpp"
#include "mereo/shapes/cone.hpp"
#include "mereo/shapes/cylinder.hpp"

namespace mereo::features::detail {
namespace {

/// Points drawn from a seed's window for a circle (more than the minimal three: each carries
/// noise about as large as a small body's sagitta over the window).
constexpr int kSamplePoints = 7;
/// Neighbours drawn for a candidate's quick local score, and the least that must fit.
constexpr int kLocalTries = 24, kLocalHits = 10;
/// Candidates of a round scored on their component.
constexpr std::size_t kScored = 24;
/// The outer wall's pixels: normals within this of the surface's (they only tell it from the
/// table, at 90 degrees, and from the inner wall, facing away), degrees.
constexpr double kNormalDeviationDeg = 60.0;
/// Robust refits of the circle to the component's points, and the Huber width of their
/// residuals, times the inlier distance.
constexpr int kRefits = 3;
constexpr double kHuber = 0.5;
/// An upright cone replaces the cylinder when it tapers by at least kMinTaper and its robust
/// (Huber) cost is under kConeCost of the cylinder's. Stereo depth gives true cylinders held
/// upright tapers of 3-8 degrees at costs of 0.7-0.9 of the cylinder's (a handle's roots, the
/// rim); the renderer's tapered cups (4-10 degrees) fit at 0.01-0.6 on most frames.
constexpr double kConeCost = 0.7;
constexpr double kMinTaper = 4.0 * M_PI / 180;
/// hold_upright: bodies found bottom-up whose axis is within acos(kHoldCos) of up (20 degrees) are
/// refitted with the axis held, but for cylinders within acos(kHeldCos) (2 degrees) already; the
/// held fit replaces the free one when its robust cost is at most kHoldWorse times the free one's.
constexpr double kHoldCos = 0.94, kHeldCos = 0.9994, kHoldWorse = 1.25;
/// grow_upright: an upright body takes the free pixels next to it that fit it with normals within
/// kGrowNormalDeg when they make it kGrowth times larger. Rendered stereo seeds 6000-6099, two
/// primitive seeds: mug recall 0.67-0.79 without (per 50 frames), 0.805 with (at 60 degrees a
/// Kinect-like mug's body took its handle's roots, and bent).
constexpr double kGrowth = 1.1, kGrowNormalDeg = 45.0;
/// grow_upright: how far below the heights the segment spanned it may grow, metres (not above:
/// a lid's fattened edge would lift the body's end over the lid, which would then look open).
constexpr double kGrowReach = 0.01;
/// An upright cylinder replaces the segments it competes with (leaning ones, narrow strips) whose
/// pixels it takes most of when it holds at least this many times their pixels together: a
/// leaning cone hugging the visible side of a partly hidden body holds about as many as the
/// upright body does (stereo seed 5010).
constexpr double kReplace = 1.0;
/// The search stops after this many rounds in a row whose best candidate did not hold.
constexpr int kMaxFailed = 6;
/// Segments found bottom-up whose axis is within acos(kUprightCos) of up (10 degrees) are upright
/// bodies already: no seeds are drawn on them, unless they are narrow strips (narrow_strip).
constexpr double kUprightCos = 0.985;
/// Two bodies standing on the support cannot overlap: a circle that overlaps an upright body's by
/// more than this (metres, the noise of two fits) is no body (a circle fitted to a mug's handle
/// beside its body).
constexpr double kOverlapTolerance = 0.005;
/// Of two upright bodies that would overlap, a new one holding this many times the other's pixels
/// displaces it: the first found is not always the true one (stereo seed 7012: a 12 cm circle
/// fitted about a mug's squared handle, 598 pixels, kept a far mug's body, 1598, out until the
/// search replaced it eight rounds later, after its last try at the far mug).
constexpr double kDisplace = 2.0;
/// The widest upright body looked for, metres (the container models' widest body): wider circles
/// are the walls and furniture of a room.
constexpr double kMaxUprightRadius = 0.15;
/// A body stands on the support: the lowest of its points (the kFootQuantile-th of their heights)
/// is at most kMaxFoot above it, metres (a chair's column stands on its base, above the floor).
constexpr double kMaxFoot = 0.04, kFootQuantile = 0.05;
/// foot_hidden: of a body's lowest pixels (within kLowBand of its foot), at least kHiddenShare
/// look down the image onto kRun points in a row higher than themselves by more than kAbove
/// metres, which stand in front of its wall (rendered stereo seed 5020: a mug behind a cup that
/// hides its lower half, its foot 5 cm up, was no body on the support).
constexpr double kAbove = 0.01, kLowBand = 0.01, kHiddenShare = 0.5;
constexpr int kRun = 3;
/// outer_walls: a vessel's wall is kMinWall to kMaxWall thick (metres), its outer wall is looked
/// for from kWallFloor above the support (below, the table's pixels would fill the ring about it)
/// and kept when at least kMinOuterPixels pixels fit it, kMinAtRim of them next to the inside.
constexpr double kMinWall = 0.002, kMaxWall = 0.012, kWallFloor = 0.01;
constexpr std::size_t kMinOuterPixels = 80;
constexpr std::ptrdiff_t kMinAtRim = 10;
/// The most an upright cone may taper and still be searched for a handle, radians (tapered mugs
/// take up to ~10 degrees; stereo noise and a handle's roots give cylinders 3-8).
constexpr double kMaxHandledTaper = 12.0 * M_PI / 180;

using mereo::detail::Plane2;

/// The circle through points (algebraic fit, Kasa): centre and radius; false when degenerate.
bool circle_through(const Eigen::Vector2d* q, int n, Eigen::Vector2d& centre, double& radius) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  const Eigen::Vector2d m = [&] {
    Eigen::Vector2d s = Eigen::Vector2d::Zero();
    for (int k = 0; k < n; ++k) s += q[k];
    return Eigen::Vector2d(s / n);
  }();
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d p = q[k] - m;  // centred: better conditioned
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    A += row * row.transpose();
    b += row * p.squaredNorm();
  }
  Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
  if (ldlt.info() != Eigen::Success || std::abs(A.determinant()) < 1e-30) return false;
  const Eigen::Vector3d s = ldlt.solve(b);
  centre = m + 0.5 * s.head<2>();
  const double r2 = s(2) + 0.25 * s.head<2>().squaredNorm();
  if (!(r2 > 0) || !s.allFinite()) return false;
  radius = std::sqrt(r2);
  return true;
}

/// The circle refitted to the points by Gauss-Newton on their distances with Huber weights of
/// width `huber` (metres).
void refit_circle(const std::vector<Eigen::Vector2d>& q, double huber, Eigen::Vector2d& c, double& r) {
  for (int it = 0; it < 10; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    for (const auto& p : q) {
      const Eigen::Vector2d d = p - c;
      const double len = d.norm();
      if (len < 1e-9) continue;
      const double res = len - r, w = std::abs(res) <= huber ? 1.0 : huber / std::abs(res);
      const Eigen::Vector3d J(-d.x() / len, -d.y() / len, -1.0);
      JtJ += w * J * J.transpose();
      Jtr += w * J * res;
    }
    const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return;
    c += step.head<2>(), r += step(2);
    if (step.norm() < 1e-6) return;
  }
}

/// The Huber loss of a residual, quadratic within `width`, linear beyond.
double huber_loss(double res, double width) {
  const double a = std::abs(res);
  return a <= width ? a * a : width * (2 * a - width);
}

/// The upright cone that fits the points better than the cylinder (c, r) does, if one does: the
/// distance from the axis grows linearly with height, r + k t (t from the points' mean height
/// `t0`), fitted by Gauss-Newton with Huber weights; it is kept when its taper is at least
/// kMinTaper and its robust cost under kConeCost of the cylinder's.
std::optional<shapes::Cone> upright_cone(const Plane2& pl, const std::vector<Eigen::Vector3d>& pts, double huber,
                                         const Eigen::Vector2d& c0, double r0) {
  if (pts.size() < 20) return std::nullopt;
  double t0 = 0;
  for (const auto& x : pts) t0 += pl.up.dot(x);
  t0 /= double(pts.size());
  const auto cost = [&](const Eigen::Vector4d& p) {  // cx, cy, r, k
    double sum = 0;
    for (const auto& x : pts) sum += huber_loss((pl.of(x) - p.head<2>()).norm() - p(2) - p(3) * (pl.up.dot(x) - t0), huber);
    return sum;
  };
  Eigen::Vector4d p(c0.x(), c0.y(), r0, 0.0);
  const double cylinder_cost = cost(p);
  for (int it = 0; it < 10; ++it) {
    Eigen::Matrix4d JtJ = Eigen::Matrix4d::Zero();
    Eigen::Vector4d Jtr = Eigen::Vector4d::Zero();
    for (const auto& x : pts) {
      const Eigen::Vector2d d = pl.of(x) - p.head<2>();
      const double len = d.norm(), t = pl.up.dot(x) - t0;
      if (len < 1e-9) continue;
      const double res = len - p(2) - p(3) * t, w = std::abs(res) <= huber ? 1.0 : huber / std::abs(res);
      const Eigen::Vector4d J(-d.x() / len, -d.y() / len, -1.0, -t);
      JtJ += w * J * J.transpose();
      Jtr += w * J * res;
    }
    const Eigen::Vector4d step = JtJ.ldlt().solve(-Jtr);
    if (!step.allFinite()) return std::nullopt;
    p += step;
    if (step.norm() < 1e-7) break;
  }
  const double angle = std::atan(std::abs(p(3)));
  if (!(p(2) > 0) || angle < kMinTaper || angle > shapes::Cone::kMaxAngle ||
      !(cost(p) < kConeCost * cylinder_cost))
    return std::nullopt;
  shapes::Cone k;
  k.axis = p(3) > 0 ? pl.up : Eigen::Vector3d(-pl.up);
  k.point = pl.e1 * p(0) + pl.e2 * p(1) + pl.up * t0;
  k.radius = p(2);
  k.angle = angle;
  return k;
}

/// The circle in the support plane of an upright cylinder or cone (its radius at its point).
struct Circle {
  Eigen::Vector2d c;
  double r;
};
std::optional<Circle> upright_circle(const Plane2& pl, const Segment& s) {
  const auto axis = s.direction();
  if (!axis || std::abs(axis->normalized().dot(pl.up)) <= kUprightCos || s.inward) return std::nullopt;
  if (const auto* c = s.get_if<shapes::Cylinder>()) return Circle{pl.of(c->point), c->radius};
  if (const auto* k = s.get_if<shapes::Cone>()) return Circle{pl.of(k->point), k->radius};
  return std::nullopt;
}

shapes::Cylinder upright_cylinder(const Plane2& pl, const Eigen::Vector2d& c, double r, double height_along) {
  shapes::Cylinder s;
  s.axis = pl.up;
  s.point = pl.e1 * c.x() + pl.e2 * c.y() + pl.up * height_along;
  s.radius = r;
  return s;
}

/// The robust (Huber, width `huber`) cost of the points against the surface of s.
double huber_cost(const Segment& s, const std::vector<Eigen::Vector3d>& pts, double huber) {
  double sum = 0;
  for (const auto& x : pts) sum += huber_loss(s.signed_distance(x), huber);
  return sum;
}

/// A body's points (unfiltered) for a circle refit with the axis held: their projections on the
/// support plane, their mean height along its normal and the Huber width at their mean depth.
struct HeldPoints {
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> q;
  double height = 0, huber = 0;
  HeldPoints(const Pixels& f, const Plane2& pl, const std::vector<int>& pix) {
    pts.reserve(pix.size()), q.reserve(pix.size());
    double along = 0, zsum = 0;
    for (int i : pix) {
      pts.push_back(f.raw(i));
      q.push_back(pl.of(pts.back())), along += pl.up.dot(pts.back()), zsum += pts.back().z();
    }
    const double n = double(pts.size());
    height = along / n, huber = kHuber * f.eps(zsum / n);
  }
};

/// An upright body's segment that spans less than kStrip of its circle's diameter across the view:
/// a narrow strip of a wall fitted with too wide a circle (stereo seed 8045: a strip 33 mm wide
/// of a 76 mm mug, fitted with a radius of 100 mm). A body seen from outside shows most of its
/// width.
bool narrow_strip(const Pixels& f, const Plane2& pl, const Segment& s) {
  constexpr double kStrip = 0.5, kQuantile = 0.02;
  const auto circle = upright_circle(pl, s);
  if (!circle || s.pixels.size() < 20 || !(circle->c.norm() > 0)) return false;
  const Eigen::Vector2d d = circle->c.normalized(), t(-d.y(), d.x());
  std::vector<double> across;
  across.reserve(s.pixels.size());
  for (int i : s.pixels) across.push_back(t.dot(pl.of(f.raw(i))));
  std::sort(across.begin(), across.end());
  const double span = across[std::size_t((1 - kQuantile) * double(across.size() - 1))] -
                      across[std::size_t(kQuantile * double(across.size()))];
  return span < kStrip * 2 * circle->r;
}

}  // namespace

bool foot_hidden(const Pixels& g, const Eigen::Vector4d& support, const std::vector<int>& pix, double foot) {
  const double norm = support.head<3>().norm();
  const Eigen::Vector3d up = support.head<3>() / norm;
  const auto height = [&](const Eigen::Vector3d& x) { return (support.head<3>().dot(x) + support(3)) / norm; };
  int low = 0, hidden = 0;
  for (int i : pix) {
    const Eigen::Vector3d x = g.p(i);
    const double h = height(x);
    if (!(h <= foot + kLowBand) || !(x.z() > 0.1)) continue;
    ++low;
    // the image step of a point moving down along -up from x, per metre
    const Eigen::Vector3d d = -up;
    const Eigen::Vector2d step(g.focal * (d.x() * x.z() - x.x() * d.z()) / (x.z() * x.z()),
                               g.focal * (d.y() * x.z() - x.y() * d.z()) / (x.z() * x.z()));
    const double per_m = step.norm();
    if (!(per_m > 1e-6)) continue;
    const Eigen::Vector2d dir = step / per_m;
    const int reach = int(std::ceil(per_m * h)) + 2;
    const double u0 = i % g.W, v0 = i / g.W;
    // down to the support: kRun points in a row higher than it stand in front of the wall (below a
    // wall in the image lie its lower part, the support in front of it, or what stands in front;
    // a base the body stands on, as a drill's battery under its grip, lies no higher than its foot)
    int run = 0;
    for (int k = 1; k <= reach && run < kRun; ++k) {
      const int u = int(std::lround(u0 + dir.x() * k)), v = int(std::lround(v0 + dir.y() * k));
      if (u < 0 || u >= g.W || v < 0 || v >= g.H) break;
      const Eigen::Vector3d y = g.p(v * g.W + u);
      if (y.allFinite()) run = height(y) > h + kAbove ? run + 1 : 0;
    }
    hidden += run >= kRun;
  }
  return low > 0 && double(hidden) >= kHiddenShare * double(low);
}

void hold_upright(const Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, double min_r, double max_r) {
  const Eigen::Vector3d up = support.head<3>();
  if (!(up.norm() > 0.5)) return;
  const Plane2 pl(up);
  for (Segment& s : out) {
    const auto axis = s.direction();
    if (!axis || s.inward || !(s.is<shapes::Cylinder>() || s.is<shapes::Cone>()) || s.pixels.size() < 20) continue;
    const double c = std::abs(axis->normalized().dot(pl.up));
    if (c < kHoldCos || (s.is<shapes::Cylinder>() && c > kHeldCos)) continue;
    const HeldPoints h(f, pl, s.pixels);
    const auto& pts = h.pts;
    const double huber = h.huber;
    // the circle where the free fit's axis meets the points' mean height
    const Eigen::Vector3d o = s.origin(), a = axis->normalized();
    const double t = (h.height - pl.up.dot(o)) / a.dot(pl.up);
    Eigen::Vector2d centre = pl.of(o + t * a);
    double r = s.is<shapes::Cylinder>() ? s.as<shapes::Cylinder>().radius : s.as<shapes::Cone>().radius_at(t);
    refit_circle(h.q, huber, centre, r);
    if (!(r >= min_r && r <= max_r)) continue;
    Segment held{Geometry(upright_cylinder(pl, centre, r, h.height))};
    if (auto cone = upright_cone(pl, pts, huber, centre, r); cone && cone->radius >= min_r && cone->radius <= max_r)
      held.shape = Geometry(*cone);
    // it may fit a little worse: the noise leaned the free fit (a tapered cup found bottom-up as
    // a leaning cylinder is a cone once held; so are a few jars, whose lid tells them apart)
    if (!(huber_cost(held, pts, huber) <= kHoldWorse * huber_cost(s, pts, huber))) continue;
    // the same pixels, the held shape (its ends and bend are measured after, as every segment's;
    // its colour stays)
    s.shape = held.shape;
    describe(f, s, std::move(s.pixels), nullptr);
    set_residual(s, pts);
  }
}

std::vector<std::vector<int>> grow_upright(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out,
                                           double min_r, double max_r, const ColorImage* color) {
  std::vector<std::vector<int>> added(out.size());
  const Eigen::Vector3d up = support.head<3>();
  if (!(up.norm() > 0.5)) return added;
  const Plane2 pl(up);
  DetectOptions local = f.o;
  local.normal_deviation_deg = std::max(f.o.normal_deviation_deg, kGrowNormalDeg);
  for (std::size_t k = 0; k < out.size(); ++k) {
    Segment& s = out[k];
    if (s.inward || !(s.is<shapes::Cylinder>() || s.is<shapes::Cone>()) || !upright_circle(pl, s)) continue;
    Pixels g(f, local);
    for (int i : s.pixels) g.free[std::size_t(i)] = 1;
    // within the heights the segment spans (and kGrowReach below): a rim's or a lid's fattened
    // edge turns the normals upward into the loose deviation, and would lift the body's end
    double lo = 1e300, hi = -1e300;
    for (int i : s.pixels) lo = std::min(lo, pl.up.dot(g.p(i))), hi = std::max(hi, pl.up.dot(g.p(i)));
    lo -= kGrowReach;
    // the segment's pixels and the free ones connected to them that fit it, normals loosely
    std::vector<std::uint8_t> in(g.free.size(), 0);
    std::vector<int> pix;
    for (int i : s.pixels) in[std::size_t(i)] = 1, pix.push_back(i);
    for (std::size_t head = 0; head < pix.size(); ++head) {
      const int i = pix[head], v = i / g.W, u = i % g.W;
      const int nb[4][2] = {{v - 1, u}, {v + 1, u}, {v, u - 1}, {v, u + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= g.H || q[1] < 0 || q[1] >= g.W) continue;
        const int j = q[0] * g.W + q[1];
        if (in[std::size_t(j)] || !g.free[std::size_t(j)] || !g.fits(s, j, +1)) continue;
        if (const double h = pl.up.dot(g.p(j)); h < lo || h > hi) continue;
        in[std::size_t(j)] = 1, pix.push_back(j);
      }
    }
    if (double(pix.size()) < kGrowth * double(s.pixels.size())) continue;
    const HeldPoints h(g, pl, pix);
    const auto& pts = h.pts;
    if (const auto* cyl = s.get_if<shapes::Cylinder>()) {
      // the circle refitted to all of them (the axis held)
      Eigen::Vector2d c = pl.of(cyl->point);
      double r = cyl->radius;
      refit_circle(h.q, h.huber, c, r);
      if (r >= min_r && r <= max_r) s.shape = Geometry(upright_cylinder(pl, c, r, h.height));
    }
    std::vector<int> before = s.pixels;
    std::sort(before.begin(), before.end());
    describe(g, s, std::move(pix), color);
    set_residual(s, pts);
    for (int i : s.pixels) f.free[std::size_t(i)] = 0;
    std::set_difference(s.pixels.begin(), s.pixels.end(), before.begin(), before.end(), std::back_inserter(added[k]));
  }
  return added;
}

void outer_walls(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, double min_r, double max_r,
                 const ColorImage* color) {
  const Eigen::Vector3d up = support.head<3>();
  const double norm = up.norm();
  if (!(norm > 0.5)) return;
  const Plane2 pl(up);
  DetectOptions local = f.o;
  local.normal_deviation_deg = std::max(f.o.normal_deviation_deg, kNormalDeviationDeg);
  Pixels g(f, local);
  const auto height = [&](const Eigen::Vector3d& x) { return (up.dot(x) + support(3)) / norm; };
  const Eigen::Vector2d eye = pl.of(Eigen::Vector3d::Zero());  // the camera, on the plane
  const std::size_t found = out.size();
  for (std::size_t k = 0; k < found; ++k) {
    const auto* inner = out[k].get_if<shapes::Cylinder>();
    if (!inner || !out[k].inward || std::abs(inner->axis.normalized().dot(pl.up)) <= kUprightCos) continue;
    const Eigen::Vector2d c = pl.of(inner->point);
    const double r = inner->radius;
    if (r + kMaxWall > max_r) continue;
    // an outer wall about it found already
    if (std::any_of(out.begin(), out.end(), [&](const Segment& s) {
          const auto circle = upright_circle(pl, s);
          return circle && (circle->c - c).norm() < r;
        }))
      continue;
    // the free pixels on the camera's side of the axis, from the support up to the inside's top,
    // up to a wall's thickness (and the noise) beyond the inside's radius
    double top = -INFINITY;
    for (int i : out[k].pixels) top = std::max(top, height(g.p(i)));
    std::vector<int> near;
    std::vector<double> dist;
    for (int i = 0; i < g.H * g.W; ++i) {
      if (!g.free[std::size_t(i)]) continue;
      const Eigen::Vector3d x = g.p(i);
      if (!x.allFinite()) continue;
      const double h = height(x);
      const Eigen::Vector2d d = pl.of(x) - c;
      if (h < kWallFloor || h > top + kGrowReach || d.dot(eye - c) <= 0) continue;
      const double tol = g.eps(x.z());
      if (d.norm() < r - tol || d.norm() > r + kMaxWall + tol) continue;
      near.push_back(i), dist.push_back(d.norm());
    }
    if (near.size() < kMinOuterPixels) continue;
    // its radius: the median distance (the centre held), a wall's thickness at most beyond
    std::nth_element(dist.begin(), dist.begin() + std::ptrdiff_t(dist.size() / 2), dist.end());
    const double r_out = std::clamp(dist[dist.size() / 2], r + kMinWall, r + kMaxWall);
    if (r_out < min_r) continue;
    Segment s{Geometry(upright_cylinder(pl, c, r_out, pl.up.dot(inner->point)))};
    std::vector<int> pix;
    for (int i : near)
      if (g.fits(s, i, +1)) pix.push_back(i);
    if (pix.size() < kMinOuterPixels) continue;
    // the wall meets the inside at the rim: next to it in the image, within the rim's width
    std::vector<std::uint8_t> by_inside(g.free.size(), 0);
    for (int i : out[k].pixels) {
      const int reach = 2 + int(std::ceil(g.focal * (kMaxWall + kMinWall) / std::max(0.1, g.p(i).z())));
      for (int v = std::max(0, i / g.W - reach); v <= std::min(g.H - 1, i / g.W + reach); ++v)
        for (int u = std::max(0, i % g.W - reach); u <= std::min(g.W - 1, i % g.W + reach); ++u) by_inside[std::size_t(v * g.W + u)] = 1;
    }
    if (std::count_if(pix.begin(), pix.end(), [&](int i) { return by_inside[std::size_t(i)] != 0; }) < kMinAtRim) continue;
    const HeldPoints h(g, pl, pix);
    s.shape = Geometry(upright_cylinder(pl, c, r_out, h.height));
    describe(g, s, std::move(pix), color);
    set_residual(s, h.pts);
    if (s.inward) continue;
    for (int i : s.pixels) f.free[std::size_t(i)] = 0;
    out.push_back(std::move(s));
  }
}

void search_upright(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, int min_support, double min_r,
                    double max_r, int max_count, const ColorImage* color) {
  const Eigen::Vector3d up = support.head<3>();
  if (!(up.norm() > 0.5) || max_count <= 0) return;
  max_r = std::min(max_r, kMaxUprightRadius);
  const Plane2 pl(up);
  DetectOptions local = f.o;
  local.normal_deviation_deg = std::max(f.o.normal_deviation_deg, kNormalDeviationDeg);
  Pixels g(f, local);
  // the segments found so far compete, but for the upright bodies (what this search would find
  // again) that are no narrow strips: their pixels are searched too
  std::vector<int> owner(std::size_t(g.H) * g.W, -1);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto axis = out[k].direction();
    const bool axial = out[k].is<shapes::Cylinder>() || out[k].is<shapes::Cone>();
    if (axial && axis && std::abs(axis->normalized().dot(pl.up)) > kUprightCos && !narrow_strip(g, pl, out[k])) continue;
    for (int i : out[k].pixels) owner[std::size_t(i)] = int(k), g.free[std::size_t(i)] = 1;
  }
  std::vector<bool> dropped(out.size(), false);
  const int step = std::max(1, f.o.score_step);
  std::vector<std::uint8_t> seedable(g.free);  // (not where a candidate was tried)
  std::vector<int> pool;
  for (int v = 0; v < g.H; v += step)
    for (int u = 0; u < g.W; u += step)
      if (seedable[v * g.W + u]) pool.push_back(v * g.W + u);

  int found = 0;
  for (int round = 0, failed = 0; round < f.o.max_iterations && found < max_count && failed < kMaxFailed; ++round) {
    pool.erase(std::remove_if(pool.begin(), pool.end(), [&](int i) { return !g.free[i] || !seedable[i]; }), pool.end());
    if (pool.size() < std::size_t(kSamplePoints)) break;
    const int count = std::max(1, f.o.candidates_per_iteration / 2);
    std::vector<std::vector<Candidate>> per(count);
    tbb::parallel_for(0, count, [&](int t) {
      ::mereo::detail::TaskRandom rng(std::uint64_t(f.o.seed) + 0x5eedULL, std::uint64_t(round), std::uint64_t(t));
      const int seed = pool[std::size_t(rng.below(pool.size()))];
      const Eigen::Vector3d p0 = g.p(seed);
      const int rpx = std::max(3, int(f.o.sample_radius * g.focal / p0.z()));
      auto neighbour = [&]() -> int {
        for (int tries = 0; tries < 16; ++tries) {
          const int v = seed / g.W + rng.below(2 * rpx + 1) - rpx, u = seed % g.W + rng.below(2 * rpx + 1) - rpx;
          if (v < 0 || v >= g.H || u < 0 || u >= g.W) continue;
          const int j = v * g.W + u;
          if (j != seed && g.free[j]) return j;
        }
        return -1;
      };
      Eigen::Vector2d q[kSamplePoints];
      q[0] = pl.of(p0);
      for (int k = 1; k < kSamplePoints; ++k) {
        const int j = neighbour();
        if (j < 0) return;
        q[k] = pl.of(g.p(j));
      }
      Eigen::Vector2d c;
      double r = 0;
      if (!circle_through(q, kSamplePoints, c, r) || r < min_r || r > max_r) return;
      // the wall seen from outside: the axis lies beyond the seed, along its ray
      const shapes::Cylinder cyl = upright_cylinder(pl, c, r, pl.up.dot(p0));
      if ((cyl.point - p0).dot(p0) <= 0) return;
      const Segment s{Geometry(cyl)};
      int hits = 0;
      for (int m = 0; m < kLocalTries && hits + kLocalTries - m >= kLocalHits; ++m) {
        const int j = neighbour();
        hits += j >= 0 && g.fits(s, j, +1);
      }
      if (hits >= kLocalHits && g.fits(s, seed, +1)) per[t].push_back({s, seed, double(hits)});
    });
    std::vector<Candidate> cands;
    for (auto& v : per)
      for (auto& c : v) cands.push_back(std::move(c));
    if (cands.empty()) break;
    std::stable_sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    cands.resize(std::min(cands.size(), kScored));
    tbb::parallel_for(std::size_t(0), cands.size(), [&](std::size_t k) {
      cands[k].score = double(g.component(cands[k].s, cands[k].seed, step).size() * step * step);
    });
    std::size_t best = 0;
    for (std::size_t k = 1; k < cands.size(); ++k)
      if (cands[k].score > cands[best].score) best = k;
    if (cands[best].score < min_support) break;
    // refine: the circle refitted to the component's points (unfiltered), the axis held
    Segment s = cands[best].s;
    const int seed = cands[best].seed;
    std::vector<int> pix, component;  // (a failed candidate's first component is seeded no more:
                                      // the next rounds would draw it again)
    for (int k = 0; k < kRefits; ++k) {
      pix = g.component(s, seed, 1);
      if (k == 0) component = pix;
      if (pix.size() < 6) break;
      const HeldPoints h(g, pl, pix);
      auto& cyl = s.as<shapes::Cylinder>();
      Eigen::Vector2d c = pl.of(cyl.point);
      double r = cyl.radius;
      refit_circle(h.q, h.huber, c, r);
      if (!(r >= min_r && r <= max_r)) {
        // flatter than any body (a box's face): the whole surface that fits the refit circle is
        // seeded no more, or the next rounds draw strips of it one by one
        if (r > max_r && std::isfinite(r) && std::isfinite(c.x()) && std::isfinite(c.y())) {
          cyl = upright_cylinder(pl, c, r, h.height);
          const auto face = g.component(s, seed, 1);
          component.insert(component.end(), face.begin(), face.end());
        }
        pix.clear();
        break;
      }
      cyl = upright_cylinder(pl, c, r, h.height);
    }
    if (!pix.empty()) {
      // a tapered cup: the cone, when it fits clearly better
      const HeldPoints h(g, pl, pix);
      const auto& cyl = s.as<shapes::Cylinder>();
      if (auto cone = upright_cone(pl, h.pts, h.huber, pl.of(cyl.point), cyl.radius);
          cone && cone->radius >= min_r && cone->radius <= max_r)
        s = Segment{Geometry(*cone)};
      pix = g.component(s, seed, 1);
    }
    // it replaces the competing segments whose pixels it takes most of, when it holds at least as
    // many as they did together (a wavy body split into a steep cone and a plane)
    std::vector<std::size_t> overlap(out.size(), 0);
    for (int i : pix)
      if (owner[std::size_t(i)] >= 0) ++overlap[std::size_t(owner[std::size_t(i)])];
    std::size_t replaced = 0;
    std::vector<bool> replaces(out.size(), false);
    for (std::size_t k = 0; k < out.size(); ++k)
      if (!dropped[k] && 2 * overlap[k] > out[k].pixels.size()) replaces[k] = true, replaced += out[k].pixels.size();
    // (the segments that keep their place keep their pixels)
    pix.erase(std::remove_if(pix.begin(), pix.end(),
                             [&](int i) { return owner[std::size_t(i)] >= 0 && !replaces[std::size_t(owner[std::size_t(i)])]; }),
              pix.end());
    // a body stands on the support: its foot is near the plane
    bool floating = true;
    if (pix.size() >= 10) {
      std::vector<double> heights;
      heights.reserve(pix.size());
      const double norm = up.norm();
      for (int i : pix) heights.push_back((up.dot(g.raw(i)) + support(3)) / norm);
      const auto q = heights.begin() + std::ptrdiff_t(kFootQuantile * double(heights.size()));
      std::nth_element(heights.begin(), q, heights.end());
      floating = *q > kMaxFoot && !foot_hidden(g, support, pix, *q);
    }
    // bodies standing on the support do not overlap (the ones it replaces aside): of two that
    // would, one holding kDisplace times the other's pixels displaces it
    bool overlaps = floating;
    if (const auto mine = upright_circle(pl, s))
      for (std::size_t k = 0; k < out.size() && !overlaps; ++k)
        if (!dropped[k] && !replaces[k])
          if (const auto other = upright_circle(pl, out[k]);
              other && (mine->c - other->c).norm() < mine->r + other->r - kOverlapTolerance) {
            if (double(pix.size()) >= kDisplace * double(out[k].pixels.size()))
              replaces[k] = true;
            else
              overlaps = true;
          }
    if (overlaps || int(pix.size()) < min_support || double(pix.size()) < kReplace * double(replaced)) {
      seedable[std::size_t(seed)] = 0;
      for (int i : pix) seedable[std::size_t(i)] = 0;
      for (int i : component) seedable[std::size_t(i)] = 0;
      ++failed;
      continue;
    }
    for (std::size_t k = 0; k < out.size(); ++k) {
      if (!replaces[k]) continue;
      dropped[k] = true;
      for (int i : out[k].pixels) owner[std::size_t(i)] = -1, f.free[std::size_t(i)] = 1;
    }
    {
      std::vector<Eigen::Vector3d> pts;
      pts.reserve(pix.size());
      for (int i : pix) pts.push_back(g.raw(i));
      set_residual(s, pts);
    }
    describe(g, s, std::move(pix), color);
    for (int i : s.pixels) g.free[i] = 0, f.free[i] = 0, owner[std::size_t(i)] = -1;
    out.push_back(std::move(s));
    dropped.push_back(false);
    ++found, failed = 0;
  }
  std::vector<Segment> kept;
  for (std::size_t k = 0; k < out.size(); ++k)
    if (!dropped[k]) kept.push_back(std::move(out[k]));
  out = std::move(kept);
}

std::optional<Segment> upright_cone_as_cylinder(const Eigen::Vector4d& support, const Segment& s) {
  const auto* k = s.get_if<shapes::Cone>();
  const Eigen::Vector3d up = support.head<3>();
  if (!k || s.inward || !(up.norm() > 0.5) || k->angle > kMaxHandledTaper ||
      std::abs(k->axis.normalized().dot(up.normalized())) < kHoldCos)
    return std::nullopt;
  // the widest radius: the whole wall lies within it, so none of it is taken for a handle
  shapes::Cylinder cyl = k->simplified();
  cyl.radius = std::max(k->radius_at(0.5 * k->height), k->radius_at(-0.5 * k->height));
  Segment c = s;
  c.shape = Geometry(cyl);
  return c;
}

bool hold_as_cylinder(const Pixels& f, const Eigen::Vector4d& support, Segment& s, double min_r, double max_r,
                      const ColorImage* color) {
  const auto* k = s.get_if<shapes::Cone>();
  const Eigen::Vector3d up = support.head<3>();
  if (!k || s.pixels.size() < 20 || !(up.norm() > 0.5)) return false;
  const Plane2 pl(up);
  const HeldPoints h(f, pl, s.pixels);
  Eigen::Vector2d c = pl.of(k->point);
  double r = k->radius;
  refit_circle(h.q, h.huber, c, r);
  if (!(r >= min_r && r <= max_r)) return false;
  // still clearly a cone without the handle's pixels: a tapered body (a cup beside something
  // taken for a handle) stays one
  if (upright_cone(pl, h.pts, h.huber, c, r)) return false;
  s.shape = Geometry(upright_cylinder(pl, c, r, h.height));
  describe(f, s, std::move(s.pixels), color);
  set_residual(s, h.pts);
  return true;
}

}  // namespace mereo::features::detail
