// The handle module (see mereo/features/handle.hpp): the ring fits about a body and the
// model-driven search next to it.
#include "mereo/features/handle.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "features/fit.hpp"
#include "features/pixels.hpp"
#include "mereo/signal/edges.hpp"

namespace mereo::features {

using shapes::Cylinder;
using shapes::Torus;

bool HandleOptions::plausible(const Segment& t) const {
  const auto* r = t.get_if<Torus>();
  return r && r->minor_radius >= min_minor_radius && r->minor_radius <= max_minor_radius &&
         r->major_radius >= min_major_radius && r->major_radius <= max_major_radius;
}

namespace {
/// A handle's ring spans at most about its body's height; one wider than the body's fitted
/// height by more than this (metres; a short fit of a partly seen body, a torus fitted to a
/// D-shaped handle) is not beside it as a handle. Stereo depth of a band handle at a metre and
/// more gave rings of 6.7-7 cm beside bodies 9.5-10 cm tall (seeds 7003, 7045), which no model
/// takes, and the colour image was never asked.
constexpr double kRingOverHeight = 0.025;
}  // namespace

bool HandleOptions::beside(const Cylinder& body, const Segment& t) const {
  if (!plausible(t)) return false;
  const Torus& ring = t.as<Torus>();
  const Eigen::Vector3d a = body.axis.normalized(), q = ring.center - body.point;
  return (q - a * a.dot(q)).norm() >= 0.5 * body.radius && 2 * ring.major_radius <= body.height + kRingOverHeight;
}

bool HandleOptions::in_reach(const Cylinder& body, const Eigen::Vector3d& x, double noise) const {
  const Eigen::Vector3d a = body.axis.normalized(), q = x - body.point;
  const double along = a.dot(q), rho = (q - a * along).norm();
  return rho > body.radius + noise && rho <= body.radius + max_reach &&
         std::abs(along) <= 0.5 * body.height - foot_margin;  // a handle stays off the table
}

namespace {

/// The distance from the body's axis of an attached handle's ring centre: its tube's centre line
/// enters the wall by the tube radius.
double attached_distance(double body_radius, double ring_radius, double tube_radius) {
  return body_radius + ring_radius - tube_radius;
}

/// A handle's torus from (azimuth, height, distance from the axis, ring radius, tube radius[,
/// turn]) about `body`: the ring plane holds the body's axis (turned about it by the sixth value).
Torus handle_torus(const Cylinder& body, const Eigen::VectorXd& v) {
  const Eigen::Vector3d a = body.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const Eigen::Vector3d u = std::cos(v(0)) * e1 + std::sin(v(0)) * e2;
  Torus t;
  t.center = body.point + a * v(1) + u * v(2);
  t.normal = a.cross(u).normalized();
  t.major_radius = v(3);
  t.minor_radius = v(4);
  if (v.size() > 5) t.normal = Eigen::AngleAxisd(v(5), a) * t.normal;  // the ring plane turned about the axis
  return t;
}

/// The handle fit's residuals: a point is seen on the side of the tube that faces the camera;
/// one that the fit would put on the far side costs up to a tube's diameter more (a thin tube
/// can otherwise be fitted in front of the points as well as behind them).
void handle_residuals(const Torus& t, const std::vector<Eigen::Vector3d>& pts, Eigen::VectorXd& r) {
  for (int i = 0; i < int(pts.size()); ++i) {
    Eigen::Vector3d sn;
    const double d = t.signed_distance(pts[std::size_t(i)], &sn);
    const double away = -sn.dot(-pts[std::size_t(i)].normalized());
    r(i) = d + 2 * t.minor_radius * std::max(0.0, away);
  }
}

/// (azimuth, height, distance from the axis, ring radius, tube radius) of a torus about `body`.
Eigen::VectorXd handle_params(const Cylinder& body, const Torus& t) {
  const Eigen::Vector3d a = body.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const Eigen::Vector3d q = t.center - body.point;
  const double h = a.dot(q);
  const Eigen::Vector3d radial = q - a * h;
  Eigen::VectorXd x(5);
  x << std::atan2(radial.dot(e2), radial.dot(e1)), h, radial.norm(), t.major_radius, t.minor_radius;
  return x;
}

}  // namespace

HandleTurn handle_turn(const Segment& body_segment, const Segment& t_segment, const std::vector<Eigen::Vector3d>& points) {
  HandleTurn out;
  if (points.size() < 6) return out;
  const Cylinder& body = body_segment.as<Cylinder>();
  const Torus& t = t_segment.as<Torus>();
  std::vector<Eigen::Vector3d> buffer;
  const auto& pts = detail::subsample_into(points, buffer, detail::kFitPoints);
  const int N = int(pts.size());
  const Eigen::VectorXd x0 = handle_params(body, t);
  Eigen::VectorXd r(N);
  handle_residuals(t, pts, r);
  out.rms_held = std::sqrt(r.squaredNorm() / N);
  out.rms_turned = out.rms_held;
  // the ring and its turn, the tube held; from no turn and from a turn either way (a local fit;
  // the three on their own threads, the best taken in this order)
  constexpr double kStarts[3] = {0.0, 40.0, -40.0};
  double rms[3], turn[3];
  tbb::parallel_for(0, 3, [&](int k) {
    Eigen::VectorXd y(5);
    y << x0.head<4>(), kStarts[k] * M_PI / 180.0;
    detail::levenberg_marquardt(y, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& res) {
      Eigen::VectorXd full(6);
      full << v.head<4>(), x0(4), v(4);
      handle_residuals(handle_torus(body, full), pts, res);
    });
    Eigen::VectorXd full(6), rk(N);
    full << y.head<4>(), x0(4), y(4);
    handle_residuals(handle_torus(body, full), pts, rk);
    rms[k] = std::sqrt(rk.squaredNorm() / N), turn[k] = y(4);
  });
  for (int k = 0; k < 3; ++k)
    if (rms[k] < out.rms_turned) out.rms_turned = rms[k], out.turn_deg = std::remainder(turn[k], M_PI) * 180.0 / M_PI;
  return out;
}

Segment refit_handle(const Segment& body_segment, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                     bool fix_minor) {
  const Cylinder& body = body_segment.as<Cylinder>();
  Eigen::VectorXd x = handle_params(body, t0.as<Torus>());
  if (points.size() >= 5) {
    std::vector<Eigen::Vector3d> buffer;
    const auto& pts = detail::subsample_into(points, buffer, detail::kFitPoints);
    const int N = int(pts.size());
    Eigen::VectorXd y = fix_minor ? Eigen::VectorXd(x.head<4>()) : x;
    detail::levenberg_marquardt(y, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
      Eigen::VectorXd full = x;
      full.head(v.size()) = v;
      handle_residuals(handle_torus(body, full), pts, r);
    });
    x.head(y.size()) = y;
    // A handle is attached: its tube's centre line enters the wall at its roots. A ring whose
    // centre line stays outside the wall (noisy points of the outer arc alone: a small ring
    // fitted off the wall) is refitted with it entering the wall by its tube radius
    // (distance from the axis = body radius + ring radius - tube radius).
    if (x(2) - x(3) > body.radius) {
      Eigen::VectorXd z(4);
      z << x(0), x(1), x(3), x(4);
      if (fix_minor) z.conservativeResize(3);  // (the tube held)
      auto attached = [&](const Eigen::VectorXd& v) {
        Eigen::VectorXd full = x;
        full(0) = v(0), full(1) = v(1), full(3) = v(2);
        if (v.size() > 3) full(4) = v(3);
        full(2) = attached_distance(body.radius, full(3), full(4));
        return full;
      };
      detail::levenberg_marquardt(z, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
        handle_residuals(handle_torus(body, attached(v)), pts, r);
      });
      x = attached(z);
    }
  }
  Segment s(handle_torus(body, x));
  s.id = t0.id, s.pixels = t0.pixels, s.inliers = t0.inliers;
  detail::set_residual(s, points);
  return s;
}

namespace detail {
namespace {

/// Handle hypotheses next to a body (steps 1-3 of handle.hpp). Each plausible torus is a
/// candidate scored by its pixels within epsilon. Deterministic.
std::vector<Candidate> handle_hypotheses(const Pixels& f, const Cylinder& body_shape, const Segment& body,
                                         const std::vector<int>& region, int min_support, const HandleOptions& h,
                                         const shapes::Limits& limits) {
  const Eigen::Vector3d a = body_shape.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  struct Near {
    int i;
    double theta, rho;
  };
  std::vector<Near> pts;
  for (int i : region) {
    if (!f.free[i]) continue;
    if (!h.in_reach(body_shape, f.p(i), 0.5 * f.eps(f.p(i).z()))) continue;
    const Eigen::Vector3d x = f.p(i) - body_shape.point;
    const Eigen::Vector3d radial = x - a * a.dot(x);
    pts.push_back({i, std::atan2(radial.dot(e2), radial.dot(e1)), radial.norm()});
  }
  std::vector<Candidate> out;
  if (int(pts.size()) < min_support) return out;
  const int bins = std::max(4, int(std::lround(360.0 / h.bin_deg)));
  const int window_bins = std::max(1, int(std::lround(h.window_deg / h.bin_deg)));
  std::vector<int> hist(bins, 0);
  for (const auto& q : pts) hist[std::min(bins - 1, int((q.theta + M_PI) / (2 * M_PI) * bins))]++;
  auto window = [&](int b) {
    int sum = 0;
    for (int k = -window_bins / 2; k <= window_bins / 2; ++k) sum += hist[(b + k + bins) % bins];
    return sum;
  };
  std::vector<int> peaks;
  for (int pass = 0; pass < h.max_windows; ++pass) {
    int best = -1, best_sum = 0;
    for (int b = 0; b < bins; ++b) {
      bool clear = true;
      for (int p : peaks) clear = clear && std::min((b - p + bins) % bins, (p - b + bins) % bins) > window_bins;
      if (clear && window(b) > best_sum) best = b, best_sum = window(b);
    }
    if (best < 0 || best_sum < min_support) break;
    peaks.push_back(best);
  }
  for (int peak : peaks) {
    const double theta0 = (peak + 0.5) / bins * 2 * M_PI - M_PI;
    std::vector<Eigen::Vector3d> sel;
    double sc = 0, ss = 0;
    for (const auto& q : pts) {
      const double d = std::remainder(q.theta - theta0, 2 * M_PI);
      // the fit starts from the part of the handle that stands off the wall (a finger's width):
      // next to the wall, the wall's own noisy pixels would pull it
      if (std::abs(d) > h.fit_half_width_deg * kDeg ||
          q.rho < body_shape.radius + std::max(h.min_standoff, f.eps(f.p(q.i).z())))
        continue;
      sel.push_back(f.p(q.i));
      sc += std::cos(q.theta), ss += std::sin(q.theta);
    }
    if (int(sel.size()) < min_support) continue;
    const double theta = std::atan2(ss, sc);
    const Eigen::Vector3d u = std::cos(theta) * e1 + std::sin(theta) * e2;
    double hmin = INFINITY, hmax = -INFINITY, rmax = 0;
    for (const auto& x : sel) {
      const double along = a.dot(x - body_shape.point);
      hmin = std::min(hmin, along), hmax = std::max(hmax, along);
      rmax = std::max(rmax, u.dot(x - body_shape.point));
    }
    Torus t0;
    t0.normal = a.cross(u).normalized();
    t0.minor_radius = h.start_minor_radius;  // (with the ring plane held, 4, 6 and 8 mm starts converge alike)
    t0.major_radius = std::max(h.min_start_radius, 0.5 * (hmax - hmin) - t0.minor_radius);
    t0.center = body_shape.point + a * (0.5 * (hmin + hmax)) +
                u * std::max(body_shape.radius, rmax - t0.minor_radius - t0.major_radius);
    // the ring first, with the tube radius held (trimmed), then everything if the tube radius
    // stays within the handle's range
    Segment t = refit_handle(body, Segment(t0), sel, true);
    std::vector<Eigen::Vector3d> kept;
    for (int round = 0; round < h.trim_rounds; ++round) {
      kept.clear();
      for (const auto& x : sel)
        if (std::abs(t.signed_distance(x)) <= h.trim_factor * f.eps(x.z())) kept.push_back(x);
      if (int(kept.size()) < min_support) break;
      t = refit_handle(body, t, kept, true);
    }
    auto ok = [&](const Segment& s) { return s.as<Torus>().plausible(limits); };
    if (int(kept.size()) >= min_support) {
      const Segment free_fit = refit_handle(body, t, kept);
      if (ok(free_fit)) t = free_fit;
    }
    if (!ok(t)) continue;
    int score = 0;
    for (const auto& x : sel) score += std::abs(t.signed_distance(x)) <= f.eps(x.z());
    if (score >= min_support) out.push_back({t, -1, double(score)});
  }
  return out;
}

/// The pixels of a handle torus (step 4 of handle.hpp): of the usable pixels in `region`, those
/// within epsilon whose normal faces out of the tube (a tube of a few millimetres is about as
/// thick as the normals' window, so its normals are too poor for the usual deviation), the
/// largest group connected across gaps of `pixel_gap` pixels (noise leaves holes in a band a few
/// pixels wide).
std::vector<int> handle_pixels(const Pixels& f, const Segment& t, const std::vector<int>& region, const HandleOptions& h) {
  std::vector<int> fit;
  for (int i : region)
    if (f.free[i] && f.near_facing(t, i, h.min_facing_cos)) fit.push_back(i);
  // label the connected groups among `fit` (a small set: a map from pixel to group)
  std::vector<int> group(fit.size(), -1);
  std::unordered_map<int, int> where;
  for (std::size_t k = 0; k < fit.size(); ++k) where[fit[k]] = int(k);
  int best = -1, best_size = 0, groups = 0;
  const int gap = h.pixel_gap;
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
      for (int dv = -gap; dv <= gap; ++dv)
        for (int du = -gap; du <= gap; ++du) {
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

}  // namespace

std::vector<Segment> search_handles(Pixels& f, const Segment& body, const std::vector<int>& region, int min_support,
                                    int max_count, const ColorImage* color, const shapes::Limits& limits) {
  const HandleOptions& h = f.o.handle;
  const Cylinder& body_shape = body.as<Cylinder>();
  std::vector<Segment> out;
  while (int(out.size()) < max_count) {
    const auto cands = handle_hypotheses(f, body_shape, body, region, min_support, h, limits);
    Segment best;
    std::vector<int> best_pix;
    for (const Candidate& c : cands) {
      auto pix = handle_pixels(f, c.s, region, h);
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
    auto ok = [&](const Segment& s) { return s.as<Torus>().plausible(limits); };
    auto refit_to = [&](const std::vector<Eigen::Vector3d>& pts) { return refit_handle_or_hold(body, best, pts, ok); };
    for (int round = 0; round < h.refit_rounds; ++round) {
      best = refit_to(points_of(best_pix));
      best_pix = handle_pixels(f, best, region, h);
    }
    if (int(best_pix.size()) < min_support || !ok(best)) break;
    const auto pts = points_of(best_pix);
    best = refit_to(pts);  // (the residual of the final pixels)
    // a handle's ring plane holds the body's axis; a ring whose points would rather have it
    // turned away (a ring leaning on a jar) is not one: the search stops there
    if (h.max_turn_deg < 90 && handle_turn(body, best, pts).turned_away(h)) break;
    for (int i : best_pix) f.free[i] = 0;
    describe(f, best, std::move(best_pix), color);
    out.push_back(std::move(best));
  }
  return out;
}

namespace {

/// What a handle's silhouette beside its body is (colour_handle): metres, shares.
constexpr double kColourReach = 0.065;       ///< the zone: out to this beyond the wall
constexpr double kBackgroundWidth = 0.02;    ///< ... and the background beyond it, this wide
constexpr double kColourTolerance = 0.12;    ///< colour_distance to the body's colour
constexpr double kColourContrast = 0.6;      ///< ... at most this share of the distance to the background's
constexpr double kPlaneDepth = 0.04;         ///< a pixel's depth, where it has one, this near the plane
constexpr double kMinReach = 0.025, kMaxReach = 0.062;  ///< how far the silhouette stands off the wall
constexpr double kMinSpan = 0.025;           ///< its height span, and at most kMaxSpan of the body's
constexpr double kMaxSpan = 0.95;
constexpr double kMinFill = 0.15, kMaxFill = 0.7;  ///< of its box: a loop, not a block
constexpr double kMaxBackgroundMatch = 0.3;  ///< the background beyond may look like the body this much
constexpr int kMinColourPixels = 40;
constexpr double kTube = 0.005;              ///< the torus's tube radius (a silhouette does not tell it)
constexpr double kTurnStep = M_PI / 12;      ///< the handle's plane turned about the axis in these steps
constexpr double kTurnedDepth = 0.3;         ///< a turned handle's pixels with depth, at least this share
constexpr double kMinStandoff = 0.015;       ///< where that many have depth: their median distance off the wall

/// How unlike two colours (RGB, 0-1) are, little moved by shading: their chromaticities (each
/// channel's share of the sum) apart, plus a quarter of their brightness apart.
double colour_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const double sp = p.sum() + 1e-3, sq = q.sum() + 1e-3;
  return (p / sp - q / sq).norm() + 0.25 * std::abs(sp - sq) / 3;
}

Eigen::Vector3d colour_of(const ColorImage& color, int i) {
  const std::uint8_t* c = color.data() + 3 * std::size_t(i);
  return Eigen::Vector3d(c[0], c[1], c[2]) / 255.0;
}

/// The camera as a body's own pixels show it (organized: u = f x / z + cx, the principal point
/// from the pixels' points).
struct BodyCamera {
  double focal, cx, cy;
  int W, H;

  static std::optional<BodyCamera> of(const Pixels& f, const Segment& body) {
    double cx = 0, cy = 0;
    int n = 0;
    for (int i : body.pixels) {
      const Eigen::Vector3d x = f.p(i);
      if (!(x.z() > 0)) continue;
      cx += (i % f.W) - f.focal * x.x() / x.z(), cy += (i / f.W) - f.focal * x.y() / x.z(), ++n;
    }
    if (n < 20) return std::nullopt;
    return BodyCamera{f.focal, cx / n, cy / n, f.W, f.H};
  }
  Eigen::Vector2d project(const Eigen::Vector3d& x) const {
    return {focal * x.x() / x.z() + cx, focal * x.y() / x.z() + cy};
  }
  /// The pixel index of x, or -1 outside the image or behind the camera.
  int pixel_of(const Eigen::Vector3d& x) const {
    if (!(x.z() > 0)) return -1;
    const int u = int(std::lround(focal * x.x() / x.z() + cx)), v = int(std::lround(focal * x.y() / x.z() + cy));
    return u < 0 || v < 0 || u >= W || v >= H ? -1 : v * W + u;
  }
  /// The ray's direction through image point (u, v), z = 1.
  Eigen::Vector3d ray(double u, double v) const { return {(u - cx) / focal, (v - cy) / focal, 1.0}; }
};

/// The torus that stands for a handle seen in the colour image beside `body` (colour_handle,
/// edge_handle): in the half-plane through the axis towards w, spanning heights [tmin, tmax] along
/// the axis, its outer edge `reach` off the wall and attached (no farther out than that), with
/// `pixels` (sorted) as its inliers.
Segment seen_handle(const Cylinder& body, const Eigen::Vector3d& w, double tmin, double tmax, double reach,
                    std::vector<int> pixels, const ColorImage* color) {
  const Eigen::Vector3d a = body.axis.normalized();
  Torus t;
  t.minor_radius = kTube;
  t.major_radius = std::max(0.012, 0.5 * (tmax - tmin) - kTube);
  const double d =
      std::min(body.radius + reach - t.major_radius - kTube, attached_distance(body.radius, t.major_radius, kTube));
  t.center = body.point + a * (0.5 * (tmin + tmax)) + w * d;
  t.normal = a.cross(w).normalized();
  Segment s{Geometry(t)};
  s.inliers = pixels.size();
  s.pixels = std::move(pixels);
  set_color(s, color);
  return s;
}

}  // namespace

std::optional<Segment> colour_handle(const Pixels& f, const Segment& body, const ColorImage* color, double max_turn_deg) {
  if (!color || color->empty() || body.pixels.size() < 20 || !body.is<Cylinder>()) return std::nullopt;
  const Cylinder& cyl = body.as<Cylinder>();
  const int H = f.H, W = f.W;
  const auto cam = BodyCamera::of(f, body);
  if (!cam) return std::nullopt;
  const auto colour_at = [&](int i) { return colour_of(*color, i); };
  const Eigen::Vector3d body_colour = body.mean_color.cast<double>();  // (set_color's)
  const Eigen::Vector3d a = cyl.axis.normalized(), c = cyl.point;
  const Eigen::Vector3d w0 = a.cross(c.normalized()).normalized();  // towards a limb
  const double r = cyl.radius, half = 0.5 * cyl.height;
  const double step = 0.5 * c.z() / f.focal;  // half a pixel at the body
  const auto pixel_of = [&](const Eigen::Vector3d& x) { return cam->pixel_of(x); };
  struct Zone {
    double t, rho;
    Eigen::Vector3d x;
  };
  // towards the camera, across the axis: a handle turned by `turn` about the axis lies in the
  // plane of w0 cos(turn) + v sin(turn); its pixels show only where they are beside the body's
  // silhouette (farther from the axis sideways than the radius), not in front of it or behind it
  Eigen::Vector3d v = a.cross(w0).normalized();
  if (v.dot(c) > 0) v = -v;
  // each pixel of a plane's zone and background once, found through frame-sized stamps (one
  // generation per plane) rather than by sorting the samples: a body's planes sample some 10^5
  // points, four to a pixel
  const std::size_t frame_pixels = std::size_t(H) * std::size_t(W);
  const int turns = int(std::floor(std::clamp(max_turn_deg, 0.0, 75.0) * M_PI / 180 / kTurnStep + 1e-9));
  // the planes are independent: each is searched on its own thread, and the largest silhouette
  // taken in the planes' order (the first of equal ones), as a loop over them would
  struct Seen {
    Eigen::Vector3d w;
    double tmin = 0, tmax = 0, reach = 0;
    std::vector<int> comp;
  };
  std::vector<std::optional<Seen>> seen_in(std::size_t(2 * (2 * turns + 1)));
  tbb::parallel_for(0, int(seen_in.size()), [&](int plane) {
    thread_local Stamps zone_set, background_set;
    thread_local std::vector<int> zone_index;
    if (zone_index.size() < frame_pixels) zone_index.assign(frame_pixels, -1);
    std::vector<int> zone_pixels, background;
    std::vector<Zone> zone;
    const double side = plane % 2 ? -1.0 : 1.0, turn = kTurnStep * (plane / 2 - turns), cos_turn = std::cos(turn);
    const Eigen::Vector3d w = side * cos_turn * w0 + std::sin(turn) * v;
    zone_set.clear(frame_pixels), background_set.clear(frame_pixels);
    // the zone: each pixel with its first sample
    for (double t = -half + 0.05 * cyl.height; t <= half - 0.03 * cyl.height; t += step) {
      const Eigen::Vector3d at = c + a * t;
      for (double rho = r + step; rho <= r + kColourReach + kBackgroundWidth; rho += step) {
        if (rho * cos_turn < r + step) continue;  // in front of the body or behind it
        const Eigen::Vector3d x = at + w * rho;
        const int i = pixel_of(x);
        if (i < 0) continue;
        if (rho <= r + kColourReach) {
          if (zone_set.insert(std::size_t(i)))
            zone_index[std::size_t(i)] = int(zone.size()), zone_pixels.push_back(i), zone.push_back(Zone{t, rho, x});
        } else if (background_set.insert(std::size_t(i))) {
          background.push_back(i);
        }
      }
    }
    if (zone.empty() || background.empty()) return;
    const auto zone_of = [&](int i) {  // the pixel's index in `zone`, or -1
      return zone_set.contains(std::size_t(i)) ? zone_index[std::size_t(i)] : -1;
    };
    background.erase(std::remove_if(background.begin(), background.end(), [&](int i) { return zone_of(i) >= 0; }),
                     background.end());
    std::sort(background.begin(), background.end());
    if (background.size() < 10) return;
    Eigen::Vector3d bg = Eigen::Vector3d::Zero();
    for (int i : background) bg += colour_at(i);
    bg /= double(background.size());
    auto like_body = [&](int i) {
      const Eigen::Vector3d q = colour_at(i);
      const double db = colour_distance(q, body_colour);
      return db < kColourTolerance && db < kColourContrast * colour_distance(q, bg);
    };
    int background_like = 0;
    for (int i : background) background_like += like_body(i);
    if (background_like > kMaxBackgroundMatch * double(background.size())) return;
    // the handle's pixels: the body's colour, depth near the plane or none, connected to the wall
    std::vector<char> handle(zone.size()), seen(zone.size(), 0);
    for (std::size_t k = 0; k < zone.size(); ++k) {
      const int i = zone_pixels[k];
      const Eigen::Vector3d x = f.p(i);
      const bool depth_ok = !(x.z() > 0) || std::abs(x.z() - zone[k].x.z()) < kPlaneDepth;
      handle[k] = depth_ok && like_body(i);
    }
    std::vector<int> stack, comp;
    for (std::size_t k = 0; k < zone.size(); ++k)
      if (handle[k] && zone[k].rho * std::cos(turn) <= r + 3 * step + 0.004) stack.push_back(zone_pixels[k]), seen[k] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      comp.push_back(i);
      const int u = i % W, v = i / W;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
          const int j = vv * W + uu, k = zone_of(j);
          if (k >= 0 && handle[std::size_t(k)] && !seen[std::size_t(k)]) seen[std::size_t(k)] = 1, stack.push_back(j);
        }
    }
    if (int(comp.size()) < kMinColourPixels) return;
    // where its pixels have depth, they stand off the wall (not the body's own surface beyond a
    // fit that is too narrow: a cone's wide rim, a lying can); a turned plane is told by the depth
    std::vector<double> standoff;
    for (int i : comp)
      if (const Eigen::Vector3d x = f.p(i); x.z() > 0) standoff.push_back(cyl.signed_distance(x));
    const bool with_depth = double(standoff.size()) >= kTurnedDepth * double(comp.size());
    if (!with_depth && turn != 0) return;
    if (with_depth) {
      std::nth_element(standoff.begin(), standoff.begin() + standoff.size() / 2, standoff.end());
      if (standoff[standoff.size() / 2] < kMinStandoff) return;
    }
    double tmin = INFINITY, tmax = -INFINITY, rmax = 0;
    for (int i : comp) {
      const Zone& z = zone[std::size_t(zone_of(i))];
      tmin = std::min(tmin, z.t), tmax = std::max(tmax, z.t), rmax = std::max(rmax, z.rho);
    }
    const double reach = rmax - r, span = tmax - tmin;
    std::size_t boxed = 0;
    for (const Zone& z : zone) boxed += z.t >= tmin && z.t <= tmax && z.rho <= rmax;
    const double fill = double(comp.size()) / double(std::max<std::size_t>(1, boxed));
    if (reach < kMinReach || reach > kMaxReach || span < kMinSpan || span > kMaxSpan * cyl.height || fill < kMinFill ||
        fill > kMaxFill)
      return;
    seen_in[std::size_t(plane)] = Seen{w, tmin, tmax, reach, std::move(comp)};
  });
  Seen* best = nullptr;
  for (auto& x : seen_in)
    if (x && (!best || x->comp.size() > best->comp.size())) best = &*x;
  if (!best) return std::nullopt;
  std::sort(best->comp.begin(), best->comp.end());
  return seen_handle(cyl, best->w, best->tmin, best->tmax, best->reach, std::move(best->comp), color);
}

namespace {

/// What a handle's outline beside its body is (edge_handle): metres, pixels, shares.
constexpr double kMinEdgeReach = 0.012;   ///< how far the outline stands off the limb, as seen (a handle
                                          ///< turned by 60 degrees shows half its reach)
constexpr double kWallPixels = 2.0;       ///< the outline leaves and meets the limb within this many
constexpr double kWallMetres = 0.004;     ///< pixels, or this (the body's fitted radius is noisy)
constexpr double kSideSample = 2.0;       ///< the colours either side of the outline, this far off it, pixels
constexpr int kMinRunPoints = 12;         ///< an outline's points beside the limb
constexpr double kMinLikeBody = 0.6;      ///< ... of which this share has the body's colour inside and not outside
constexpr double kEdgeHeightSlack = 0.04;  ///< the outline may reach this below the body's fitted foot, as
                                           ///< placed in the limbs' plane (a handle turned towards a camera
                                           ///< that looks down lands lower there; a far wall's fit is short)
constexpr double kMaxAxisGap = 0.02;      ///< an inside pixel's depth: at most its reach plus this from the axis

}  // namespace

std::optional<Segment> edge_handle(const Pixels& f, const Segment& body, const ColorImage* color) {
  if (!color || color->empty() || body.pixels.size() < 20 || !body.is<Cylinder>()) return std::nullopt;
  const Cylinder& cyl = body.as<Cylinder>();
  const auto cam = BodyCamera::of(f, body);
  if (!cam) return std::nullopt;
  const Eigen::Vector3d body_colour = body.mean_color.cast<double>();
  const Eigen::Vector3d a = cyl.axis.normalized(), c = cyl.point;
  const Eigen::Vector3d w0 = a.cross(c.normalized()).normalized();  // towards a limb
  Eigen::Vector3d v0 = a.cross(w0).normalized();                     // towards the camera
  if (v0.dot(c) > 0) v0 = -v0;
  const double r = cyl.radius, half = 0.5 * cyl.height, pixel = c.z() / f.focal;
  const double wall = std::max(kWallPixels * pixel, kWallMetres);
  // the zone's box in the image: the body's height, out to a handle's reach each way
  double u0 = f.W, v0i = f.H, u1 = -1, v1 = -1;
  for (double t : {-half, half})
    for (const Eigen::Vector3d& d : {w0, Eigen::Vector3d(-w0), v0})
      for (double reach : {0.0, r + kColourReach}) {
        const Eigen::Vector3d x = c + a * t + d * reach;
        if (!(x.z() > 0.01)) return std::nullopt;
        const Eigen::Vector2d q = cam->project(x);
        u0 = std::min(u0, q.x()), v0i = std::min(v0i, q.y()), u1 = std::max(u1, q.x()), v1 = std::max(v1, q.y());
      }
  const int bu0 = std::max(0, int(std::floor(u0)) - 4), bv0 = std::max(0, int(std::floor(v0i)) - 4);
  const int bu1 = std::min(f.W - 1, int(std::ceil(u1)) + 4), bv1 = std::min(f.H - 1, int(std::ceil(v1)) + 4);
  if (bu1 - bu0 < 16 || bv1 - bv0 < 16) return std::nullopt;
  ColorImage crop(bv1 - bv0 + 1, bu1 - bu0 + 1);
  for (int y = bv0; y <= bv1; ++y) std::copy_n(color->ptr(y, bu0), 3 * crop.cols(), crop.ptr(y - bv0, 0));
  signal::EdgeOptions eo;
  eo.min_chain_px = kMinRunPoints;
  eo.texture_factor = 0;  // the box is mostly the object: its median gradient is no texture's
  const auto chains = signal::detect_edges(crop, eo);

  // a point of the image in the limbs' plane (through the axis, facing the camera): height along
  // the axis, signed distance across it (+ on w0's side)
  const double plane_offset = v0.dot(c);
  struct Place {
    double t, q;
  };
  const auto place = [&](const Eigen::Vector2d& uv) -> std::optional<Place> {
    const Eigen::Vector3d d = cam->ray(uv.x(), uv.y());
    const double den = v0.dot(d);
    if (std::abs(den) < 1e-9) return std::nullopt;
    const Eigen::Vector3d x = d * (plane_offset / den) - c;
    return Place{x.dot(a), x.dot(w0)};
  };
  const auto index_of = [&](const Eigen::Vector2d& uv) {
    const int u = int(std::lround(uv.x())), v = int(std::lround(uv.y()));
    return u < 0 || v < 0 || u >= f.W || v >= f.H ? -1 : v * f.W + u;
  };
  std::optional<Segment> best;
  std::size_t best_points = 0;
  std::vector<Place> places;
  std::vector<Eigen::Vector2d> pts;
  for (const auto& chain : chains) {
    const std::size_t n = chain.points.size();
    pts.clear(), places.clear();
    for (const auto& p : chain.points) pts.emplace_back(p.x() + bu0, p.y() + bv0);
    bool placed = true;
    for (const auto& p : pts) {
      const auto pl = place(p);
      if (!pl) {
        placed = false;
        break;
      }
      places.push_back(*pl);
    }
    if (!placed) continue;
    const auto beyond = [&](std::size_t k, double side) {  // beside the limb on `side`, in the zone
      const Place& pl = places[k];
      const double out = side * pl.q - r;
      return out > wall && out <= kColourReach && pl.t > -half - kEdgeHeightSlack && pl.t < half;
    };
    const auto at_wall = [&](std::size_t k, double side) { return side * places[k].q - r <= wall; };
    for (std::size_t k = 0; k < n;) {
      const double side = places[k].q >= 0 ? 1.0 : -1.0;
      if (!beyond(k, side)) {
        ++k;
        continue;
      }
      std::size_t e = k;
      while (e + 1 < n && beyond(e + 1, side)) ++e;
      const std::size_t first = k, last = e;
      k = e + 1;
      // the run leaves the limb and comes back to it (or the chain ends there, at the junction)
      const double end_tol = wall + 2 * pixel;
      const bool left_wall = first > 0 ? at_wall(first - 1, side) : side * places[first].q - r <= end_tol;
      const bool met_wall = last + 1 < n ? at_wall(last + 1, side) : side * places[last].q - r <= end_tol;
      if (!left_wall || !met_wall || last - first + 1 < std::size_t(kMinRunPoints)) continue;
      double tmin = INFINITY, tmax = -INFINITY, reach = 0;
      for (std::size_t j = first; j <= last; ++j)
        tmin = std::min(tmin, places[j].t), tmax = std::max(tmax, places[j].t), reach = std::max(reach, side * places[j].q - r);
      const double span = tmax - tmin;
      if (reach < kMinEdgeReach || reach > kMaxReach || span < kMinSpan || span > cyl.height + kEdgeHeightSlack) continue;
      // the handle lies between the outline and the wall: its colour is the body's on that side,
      // and where it has depth that depth is near the axis (not an object behind)
      const Eigen::Vector3d centre3 = c + a * (0.5 * (tmin + tmax)) + side * w0 * r;
      const Eigen::Vector2d centre = cam->project(centre3);
      int like = 0, with_depth = 0, near_axis = 0;
      std::vector<int> inside;
      for (std::size_t j = first; j <= last; ++j) {
        const Eigen::Vector2d tangent = pts[std::min(j + 1, n - 1)] - pts[j > 0 ? j - 1 : 0];
        if (tangent.norm() < 1e-6) continue;
        Eigen::Vector2d normal(-tangent.y(), tangent.x());
        normal.normalize();
        if (normal.dot(centre - pts[j]) < 0) normal = -normal;
        const int in = index_of(pts[j] + kSideSample * normal), out = index_of(pts[j] - kSideSample * normal);
        if (in < 0 || out < 0) continue;
        const Eigen::Vector3d ci = colour_of(*color, in), co = colour_of(*color, out);
        const double di = colour_distance(ci, body_colour), dout = colour_distance(co, body_colour);
        if (di < kColourTolerance && di < kColourContrast * dout) ++like, inside.push_back(in);
        if (const Eigen::Vector3d x = f.p(in); x.z() > 0) {
          ++with_depth;
          const Eigen::Vector3d rel = x - c;
          near_axis += (rel - a * rel.dot(a)).norm() <= r + reach + kMaxAxisGap;
        }
      }
      const std::size_t points = last - first + 1;
      if (like < kMinLikeBody * double(points)) continue;
      if (with_depth >= kTurnedDepth * double(points) && 2 * near_axis < with_depth) continue;
      if (points <= best_points) continue;
      // a torus in the limb's plane
      std::sort(inside.begin(), inside.end());
      inside.erase(std::unique(inside.begin(), inside.end()), inside.end());
      best = seen_handle(cyl, side * w0, tmin, tmax, reach, std::move(inside), color);
      best_points = points;
    }
  }
  return best;
}

}  // namespace detail
}  // namespace mereo::features
