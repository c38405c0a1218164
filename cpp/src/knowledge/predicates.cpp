// The built-in fuzzy predicates and attributes of object models (see predicates.hpp).
#include "mereo/knowledge/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

namespace mereo::knowledge {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// 1 for x <= full, falling linearly to 0 at x >= zero (full < zero).
double falling(double x, double full, double zero) {
  if (std::isnan(x)) return 0.0;
  if (x <= full) return 1.0;
  if (x >= zero) return 0.0;
  return (zero - x) / (zero - full);
}
/// 0 for x <= zero, rising linearly to 1 at x >= zero + width.
double rising(double x, double zero, double width) { return std::clamp((x - zero) / width, 0.0, 1.0); }
/// The condition x >= 0 as a ramp of width 2 * tol centred on 0.
double ramp(double x, double tol) { return rising(x, -tol, 2 * tol); }

bool has_axis(const Segment& s) { return s.direction().has_value(); }

/// Angle in [0, 90] degrees between two undirected axes (both have one).
double axis_angle(const Segment& a, const Segment& b) {
  const double c = std::abs(a.direction()->normalized().dot(b.direction()->normalized()));
  return std::acos(std::min(1.0, c)) / kDeg;
}

/// p's offset from the line through `point` along `axis`, across the axis.
Eigen::Vector3d off_axis(const Eigen::Vector3d& p, const Eigen::Vector3d& point, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d q = p - point;
  return q - a * a.dot(q);
}
double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& point, const Eigen::Vector3d& axis) {
  return off_axis(p, point, axis).norm();
}

double param(const Constraint& c, const char* name, double fallback) { return c.param(name, fallback); }

/// A point's height above the support surface (ctx.support_d finite).
double height_above_support(const Eigen::Vector3d& p, const Context& ctx) {
  return ctx.up.normalized().dot(p) + ctx.support_d;
}

double near(const Segment& a, const Segment& b, const Constraint& c) {
  const double gap = std::max(a.surface_distance(b.origin()) - b.extent(), b.surface_distance(a.origin()) - a.extent());
  return falling(gap, 0.0, param(c, "max", 0.01));
}

/// The handle-on-body function of Kasprzak et al.: a torus (handle) and a cylinder (body); the
/// torus centre lies `inset` or more inside either end of the body (a handle's roots are on the
/// wall, above and below its centre). An upright body stands on the support (`rest_gap` judges
/// that): where its seen lower end lies kFootHidden or more above the support, something in front
/// hides its foot, and its lower end is taken at the support (a short body whose seen middle is
/// above its handle); a seen foot keeps its fitted end (a ring at a jar's foot is no handle).
double handle_on_body(const shapes::Torus& torus, const shapes::Cylinder& body, double tol, double inset,
                      const Context& ctx) {
  constexpr double kUprightCos = 0.9;    // within ~25 degrees of up
  constexpr double kFootHidden = 0.025;  // metres; seen feet lie within ~1 cm of the support
  Eigen::Vector3d axis = body.axis.normalized();
  double up_share = axis.dot(ctx.up.normalized());  // oriented upwards below
  if (up_share < 0) axis = -axis, up_share = -up_share;
  const Eigen::Vector3d q = torus.center - body.point;
  const double along = axis.dot(q);
  const double d = (q - axis * along).norm();
  const double inner_inside = ramp(body.radius - (d - torus.major_radius), tol);  // d - R < r_body
  const double outer_outside = ramp((d + torus.major_radius) - body.radius, tol);  // d + R > r_body
  double lower = -body.height / 2;
  if (std::isfinite(ctx.support_d) && up_share >= kUprightCos) {
    const double centre_up = height_above_support(body.point, ctx);
    if (centre_up - up_share * body.height / 2 >= kFootHidden) lower = -centre_up / up_share;
  }
  const double within_height = std::min(ramp(along - lower - inset, tol), ramp(body.height / 2 - inset - along, tol));
  return std::min({inner_inside, outer_outside, within_height});
}

double intersects(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double tol = param(c, "tolerance", 0.003), inset = param(c, "inset", 0.0);
  using shapes::Cylinder, shapes::Torus;
  if (a.is<Torus>() && b.is<Cylinder>()) return handle_on_body(a.as<Torus>(), b.as<Cylinder>(), tol, inset, ctx);
  if (a.is<Cylinder>() && b.is<Torus>()) return handle_on_body(b.as<Torus>(), a.as<Cylinder>(), tol, inset, ctx);
  return ramp(b.extent() - a.surface_distance(b.origin()), tol);
}

double parallel(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance_deg", 10.0);
  return falling(axis_angle(a, b), tol, 2 * tol);
}
double perpendicular(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance_deg", 10.0);
  return falling(90.0 - axis_angle(a, b), tol, 2 * tol);
}
/// a's ring (a torus's, an arc's) lies in a plane through b's axis: its normal is perpendicular
/// to the plane that holds b's axis and a's centre. A handle stands out from its body that way; a
/// ring that faces partly outwards (turned about a line along the axis) is a fit to something
/// else (a tapered cup's rim, a neighbour's wall). 0 when a's centre lies on b's axis (no such
/// plane). It holds perpendicular's condition too: the angle is that of both turns.
double radial(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance_deg", 10.0);
  const Eigen::Vector3d out = off_axis(a.origin(), b.origin(), *b.direction());
  if (!(out.norm() > 1e-6)) return 0.0;
  const Eigen::Vector3d plane_normal = b.direction()->normalized().cross(out).normalized();
  const double angle = std::acos(std::min(1.0, std::abs(a.direction()->normalized().dot(plane_normal)))) / kDeg;
  return falling(angle, tol, 2 * tol);
}
/// a stands out of b's wall by `min` or more: a torus's outer edge beyond a cylinder's radius
/// (d + R - r), otherwise a's farthest reach past b's surface (its extent past the distance of its
/// centre); 0 at min - margin, 1 at min.
double protrudes(const Segment& a, const Segment& b, const Constraint& c) {
  const double min = param(c, "min", 0.015), margin = param(c, "margin", 0.005);
  double reach = 0;
  if (a.is<shapes::Torus>() && b.is<shapes::Cylinder>()) {
    const auto& t = a.as<shapes::Torus>();
    const auto& cyl = b.as<shapes::Cylinder>();
    reach = distance_to_line(t.center, cyl.point, cyl.axis) + t.major_radius - cyl.radius;
  } else {
    reach = b.surface_distance(a.origin()) + a.extent();
  }
  return rising(reach, min - margin, margin);
}
double coaxial(const Segment& a, const Segment& b, const Constraint& c) {
  const double dist = param(c, "distance", 0.01);
  return std::min(parallel(a, b, c), falling(distance_to_line(b.origin(), a.origin(), *a.direction()), dist, 2 * dist));
}
double above(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double margin = param(c, "margin", 0.01);
  const double h = ctx.up.normalized().dot(a.origin() - b.origin());
  return rising(h, 0.0, margin);
}
double on(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double tol = param(c, "tolerance", 0.01);
  const Eigen::Vector3d up = ctx.up.normalized();
  const double low_a = up.dot(a.origin()) - a.half_extent_along(up);
  if (const auto* plane = b.get_if<shapes::Plane>()) {  // unbounded: a's foot on it
    const double top_b = -plane->d * up.dot(plane->normal);
    return falling(std::abs(low_a - top_b), tol, 2 * tol);
  }
  const double top_b = up.dot(b.origin()) + b.half_extent_along(up);
  const double contact = falling(std::abs(low_a - top_b), tol, 2 * tol);
  const Eigen::Vector3d dh = (a.origin() - b.origin()) - up * up.dot(a.origin() - b.origin());
  const double reach = b.extent();
  return std::min(contact, falling(dh.norm(), reach, reach + tol));
}
/// b stands under a (a leg under a seat): b's top reaches up to within `reach` of a's lowest point
/// (ramp over `margin`), and b's centre lies `min` to `max` from a's centre across up (default max:
/// a's extent: anywhere under it).
double under(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double margin = param(c, "margin", 0.05), reach = param(c, "reach", 0.2);
  const Eigen::Vector3d up = ctx.up.normalized();
  const double gap = (up.dot(a.origin()) - a.half_extent_along(up)) - (up.dot(b.origin()) + b.half_extent_along(up));
  const Eigen::Vector3d d = b.origin() - a.origin();
  const double across = (d - up * up.dot(d)).norm();
  const double lo = param(c, "min", 0.0), hi = param(c, "max", a.extent());
  return std::min({rising(gap, -margin, margin), falling(gap, reach, reach + margin),
                   Membership::range(lo, hi, margin)(across)});
}
/// Two faces of one box: each one's centre lies behind the other's surface (patches' normals face
/// the camera), as at a convex edge; a leaf standing out of its wall (a concave corner) is not.
double convex(const Segment& a, const Segment& b, const Constraint& c) {
  const double margin = param(c, "margin", 0.02);
  return std::min(rising(-a.signed_distance(b.origin()), 0.0, margin), rising(-b.signed_distance(a.origin()), 0.0, margin));
}
double same_size(const Segment& a, const Segment& b, const Constraint& c) {
  const double ratio = param(c, "ratio", 0.8);
  const double sa = a.size(), sb = b.size();
  if (!(sa > 0) || !(sb > 0)) return 0.0;
  const double q = std::min(sa, sb) / std::max(sa, sb);
  return rising(q, ratio - 0.2, 0.2);
}
double distance(const Segment& a, const Segment& b, const Constraint& c) {
  const double margin = param(c, "margin", 0.01);
  const double lo = param(c, "min", 0.0), hi = param(c, "max", 1e300);
  return Membership::range(lo, hi, margin)((a.origin() - b.origin()).norm());
}

// ---- in the image: 2-D primitives (a line, an arc: shapes/line.hpp, shapes/arc.hpp) ----

/// A 2-D primitive's direction in the image: a line's, an arc's major axis; none for the others.
std::optional<Eigen::Vector2d> image_direction(const Segment& s) {
  if (const auto* l = s.get_if<shapes::Line>(); l && l->length_px() > 0) return (l->end_px - l->start_px).normalized();
  if (const auto* a = s.get_if<shapes::Arc>(); a && a->axes_px.x() > 0)
    return Eigen::Vector2d(std::cos(a->angle_deg * kDeg), std::sin(a->angle_deg * kDeg));
  return std::nullopt;
}
/// Angle in [0, 90] degrees between two undirected image directions.
double image_angle(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::min(1.0, std::abs(a.dot(b)))) / kDeg;
}
double parallel_px(const Segment& a, const Segment& b, const Constraint& c) {
  const auto da = image_direction(a), db = image_direction(b);
  const double tol = param(c, "tolerance_deg", 10.0);
  return da && db ? falling(image_angle(*da, *db), tol, 2 * tol) : 0.0;
}
double perpendicular_px(const Segment& a, const Segment& b, const Constraint& c) {
  const auto da = image_direction(a), db = image_direction(b);
  const double tol = param(c, "tolerance_deg", 10.0);
  return da && db ? falling(90.0 - image_angle(*da, *db), tol, 2 * tol) : 0.0;
}
/// The distance from q to a polyline.
double to_polyline(const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& l) {
  double best = 1e300;
  for (std::size_t k = 0; k + 1 < l.size(); ++k) {
    const Eigen::Vector2d d = l[k + 1] - l[k];
    const double t = d.squaredNorm() > 0 ? std::clamp(d.dot(q - l[k]) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (l[k] + t * d - q).norm());
  }
  return best;
}
/// A 2-D primitive's curve in the image: a line's segment; an arc's whole ellipse, which the
/// outline meets also where the arc was not seen; empty for other classes.
std::vector<Eigen::Vector2d> image_curve(const Segment& s) {
  if (const auto* a = s.get_if<shapes::Arc>(); a && a->axes_px.x() > 0) {
    std::vector<Eigen::Vector2d> l;
    for (int k = 0; k <= 72; ++k) l.push_back(a->at(5.0 * k));
    return l;
  }
  const auto o = s.outline().pixels;
  return o.empty() ? std::vector<Eigen::Vector2d>{} : o.front();
}
/// How far apart two 2-D primitives are in the image: the nearest of either one's ends to the
/// other's curve (NaN when either is not drawn in the image).
double image_gap(const Segment& a, const Segment& b) {
  const auto oa = a.outline().pixels, ob = b.outline().pixels;
  if (oa.empty() || ob.empty()) return NAN;
  const std::vector<std::vector<Eigen::Vector2d>> ca = {oa.front(), image_curve(a)}, cb = {ob.front(), image_curve(b)};
  auto ends_to = [](const std::vector<Eigen::Vector2d>& ends, const std::vector<Eigen::Vector2d>& curve) {
    return std::min(to_polyline(ends.front(), curve), to_polyline(ends.back(), curve));
  };
  return std::min(ends_to(ca[0], cb[1]), ends_to(cb[0], ca[1]));  // ends as seen, curves whole
}
double touches_px(const Segment& a, const Segment& b, const Constraint& c) {
  const double max = param(c, "max", 4.0);
  return falling(image_gap(a, b), max, 2 * max);
}
/// b's middle off a's line (a: a line) by at least `min` pixels (0 at half of it).
double apart_px(const Segment& a, const Segment& b, const Constraint& c) {
  const auto* la = a.get_if<shapes::Line>();
  const auto cb = b.outline().pixels;
  if (!la || la->length_px() <= 0 || cb.empty()) return 0.0;
  const Eigen::Vector2d d = (la->end_px - la->start_px).normalized();
  const Eigen::Vector2d mid = (cb.front().front() + cb.front().back()) / 2;
  const double off = std::abs(d.x() * (mid - la->start_px).y() - d.y() * (mid - la->start_px).x());
  const double min = param(c, "min", 8.0);
  return rising(off, min / 2, min / 2);
}

/// b is a's ellipse carried along a's minor axis, as a cylinder's base is its rim's (a, b: arcs):
///  - major axes parallel (within tolerance_deg, 0 at twice it) and of about one size (the
///    smaller at least `ratio` of the larger, 0 at ratio - 0.2);
///  - b's centre off a's minor axis by at most 15% of a's major semi-axis (0 at 30%), and along
///    it by at least `min` pixels (0 at half of it) and at most `max` major semi-axes (0 at 1.25
///    times it: a body a few times taller than wide);
///  - b seen on its far side from a (the body hides the rest of its base): the direction from b's
///    centre to the middle of its arc within 60 degrees of the direction away from a's centre,
///    and that middle outside a's ellipse (an edge inside the opening is no base).
/// A rim seen nearly from above (axes within 15%) has no direction to hold to: there only size,
/// offset and side count.
double stacked_px(const Segment& a, const Segment& b, const Constraint& c) {
  const auto *ea = a.get_if<shapes::Arc>(), *eb = b.get_if<shapes::Arc>();
  if (!ea || !eb || !(ea->axes_px.x() > 0) || !(eb->axes_px.x() > 0)) return 0.0;
  const double tol = param(c, "tolerance_deg", 10.0), ratio = param(c, "ratio", 0.8), min = param(c, "min", 8.0),
               max = param(c, "max", 4.0);
  const Eigen::Vector2d major = *image_direction(a), minor(-major.y(), major.x());
  const bool round = ea->axes_px.x() < 1.15 * ea->axes_px.y();
  const double q = std::min(ea->axes_px.x(), eb->axes_px.x()) / std::max(ea->axes_px.x(), eb->axes_px.x());
  const Eigen::Vector2d d = eb->center_px - ea->center_px, seen = eb->at((eb->start_deg + eb->end_deg) / 2) - eb->center_px;
  const double lateral = std::abs(d.dot(major)) / ea->axes_px.x(), along = round ? d.norm() : std::abs(d.dot(minor));
  const double far = d.norm() > 0 && seen.norm() > 0 ? d.dot(seen) / (d.norm() * seen.norm()) : 0.0;
  // the middle of b's seen arc lies outside a's ellipse (not an edge inside the opening)
  const Eigen::Vector2d m = d + seen;
  const double outside = std::hypot(m.dot(major) / ea->axes_px.x(), m.dot(minor) / ea->axes_px.y());
  return std::min({round ? 1.0 : falling(image_angle(major, *image_direction(b)), tol, 2 * tol),
                   rising(q, ratio - 0.2, 0.2), round ? 1.0 : falling(lateral, 0.15, 0.3),
                   rising(along, min / 2, min / 2),
                   falling(along / ea->axes_px.x(), max, 1.25 * max), rising(far, 0.0, 0.5),
                   rising(outside, 1.0, 0.1)});
}

const std::map<std::string, std::vector<std::string>>& predicate_table() {
  static const std::map<std::string, std::vector<std::string>> t = {
      {"near", {"max"}},
      {"intersects", {"tolerance", "inset"}},
      {"parallel", {"tolerance_deg"}},
      {"perpendicular", {"tolerance_deg"}},
      {"coaxial", {"tolerance_deg", "distance"}},
      {"radial", {"tolerance_deg"}},
      {"protrudes", {"min", "margin"}},
      {"above", {"margin"}},
      {"on", {"tolerance"}},
      {"under", {"min", "max", "reach", "margin"}},
      {"convex", {"margin"}},
      {"same_size", {"ratio"}},
      {"distance", {"min", "max", "margin"}},
      {"parallel_px", {"tolerance_deg"}},
      {"perpendicular_px", {"tolerance_deg"}},
      {"touches_px", {"max"}},
      {"apart_px", {"min"}},
      {"stacked_px", {"tolerance_deg", "ratio", "min", "max"}},
  };
  return t;
}

}  // namespace

const std::vector<std::string>& builtin_predicates() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [k, v] : predicate_table()) n.push_back(k);
    return n;
  }();
  return names;
}
bool is_builtin_predicate(const std::string& name) { return predicate_table().count(name) > 0; }
const std::vector<std::string>& predicate_params(const std::string& name) {
  static const std::vector<std::string> none;
  const auto it = predicate_table().find(name);
  return it == predicate_table().end() ? none : it->second;
}

const std::vector<std::string>& attribute_names() {
  // the classes' own (mereo/shapes/*.hpp: radius, height, minor_radius...), then every segment's
  static const std::vector<std::string> names = [] {
    auto n = shape_attribute_names();
    for (const char* g : {"tilt_deg", "rest_tilt_deg", "elevation", "rest_gap", "inliers", "residual", "hue", "inward",
                          "closed_end", "open_end", "bend", "out_of_round", "rise", "top", "bottom", "span_up"})
      n.push_back(g);
    return n;
  }();
  return names;
}
bool is_attribute(const std::string& name) {
  const auto& n = attribute_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

double attribute_membership(const Segment& s, const Attribute& a, const Context& ctx) {
  const double v = attribute_value(s, a.name, ctx);
  if (const auto* p = s.get_if<shapes::Patch>(); p && std::isfinite(v)) {
    const Membership& m = a.range;
    if (a.name == "top" && p->top_hidden) return v <= m.c ? 1.0 : m(v);  // it could reach [b, c]
    if (a.name == "bottom" && p->bottom_hidden) return v >= m.b ? 1.0 : m(v);
  }
  return a.range(v);
}

double attribute_value(const Segment& s, const std::string& name, const Context& ctx) {
  // the class's own (mereo/shapes/*.cpp: radius, height, minor_radius, aspect, d...), then those
  // of every segment; an attribute the class lacks is NaN (a membership of 0)
  if (const auto v = s.attribute(name)) return *v;
  if (name == "tilt_deg" || name == "rest_tilt_deg") {
    const auto axis = s.direction();
    if (!axis) return NAN;
    const double c = std::abs(axis->normalized().dot(ctx.up.normalized()));
    const double tilt = std::acos(std::min(1.0, c)) / kDeg;
    return name == "tilt_deg" ? tilt : std::min(tilt, 90.0 - tilt);  // upright or lying
  }
  if (name == "elevation") return ctx.up.normalized().dot(s.origin());
  if (name == "rest_gap") {
    // the lowest point of a finite axial body (origin at its centre): half its height along the
    // axis's share of up, its radius across (a lying can rests with its axis a radius up)
    const auto axis = s.direction();
    const auto r = s.attribute("radius"), h = s.attribute("height");
    if (!axis || !r || !h) return NAN;
    if (!std::isfinite(ctx.support_d)) return INFINITY;  // nothing to rest on: nothing to pass through
    const Eigen::Vector3d up = ctx.up.normalized();
    const double c = std::min(1.0, std::abs(axis->normalized().dot(up)));
    return height_above_support(s.origin(), ctx) - 0.5 * *h * c - *r * std::sqrt(1 - c * c);
  }
  if (name == "top" || name == "bottom") {
    // the highest / lowest point of the part above the support (a seat's height above the floor,
    // a door's lower edge), from its extent along up; NaN without a support
    if (!std::isfinite(ctx.support_d)) return NAN;
    const Eigen::Vector3d up = ctx.up.normalized();
    const double centre = height_above_support(s.origin(), ctx), half = s.half_extent_along(up);
    return name == "top" ? centre + half : centre - half;
  }
  if (name == "span_up") return 2 * s.half_extent_along(ctx.up.normalized());
  if (name == "inliers") return double(s.inliers);
  if (name == "residual") return s.residual;
  if (name == "hue") return s.hue;
  if (name == "inward") return s.inward ? 1.0 : 0.0;
  if (name == "bend") return s.bend;
  if (name == "out_of_round") return s.out_of_round;
  if (name == "rise") {
    // where a sphere was seen, up (+1: on its top, a dome) or down (-1: below its centre, a
    // bowl's wall) along the support's normal
    const auto* sphere = s.get_if<shapes::Sphere>();
    return sphere ? sphere->cap.dot(ctx.up.normalized()) : NAN;
  }
  if (name == "closed_end" || name == "open_end") {
    // the share of the end's decided pixels on a lid (closed) or inside (open); 0 for both when
    // too few were seen to tell, so that neither an open nor a closed model is penalized
    constexpr int kMinDecided = 20;
    const int n = s.end_closed + s.end_open;
    if (n < kMinDecided) return 0.0;
    return double(name == "closed_end" ? s.end_closed : s.end_open) / n;
  }
  if (is_attribute(name)) return NAN;
  throw std::invalid_argument("unknown attribute '" + name + "'");
}

CompiledConstraint compile(const Constraint& c) {
  auto clamp01 = [](double v) { return std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0); };
  if (c.custom) {
    auto fn = c.custom;
    auto con = std::make_shared<const Constraint>(c);
    return [fn, con, clamp01](const std::vector<const Segment*>& parts, const Context& ctx) {
      return clamp01(fn(parts, *con, ctx));
    };
  }
  // the predicate functions read their parameters from a private copy of the constraint
  auto con = std::make_shared<const Constraint>(c);
  using Fn = double (*)(const Segment&, const Segment&, const Constraint&, const Context&);
  Fn f = nullptr;
  const std::string& p = c.predicate;
  if (p == "near") f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return near(a, b, k); };
  else if (p == "intersects")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return intersects(a, b, k, x); };
  else if (p == "parallel")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a) && has_axis(b) ? parallel(a, b, k) : 0.0;
    };
  else if (p == "perpendicular")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a) && has_axis(b) ? perpendicular(a, b, k) : 0.0;
    };
  else if (p == "radial")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a) && has_axis(b) ? radial(a, b, k) : 0.0;
    };
  else if (p == "protrudes")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return protrudes(a, b, k); };
  else if (p == "coaxial")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a) && has_axis(b) ? coaxial(a, b, k) : 0.0;
    };
  else if (p == "above") f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return above(a, b, k, x); };
  else if (p == "on") f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return on(a, b, k, x); };
  else if (p == "under")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return under(a, b, k, x); };
  else if (p == "convex")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return convex(a, b, k); };
  else if (p == "same_size")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return same_size(a, b, k); };
  else if (p == "distance")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return distance(a, b, k); };
  else if (p == "parallel_px")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return parallel_px(a, b, k); };
  else if (p == "perpendicular_px")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return perpendicular_px(a, b, k); };
  else if (p == "touches_px")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return touches_px(a, b, k); };
  else if (p == "apart_px")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return apart_px(a, b, k); };
  else if (p == "stacked_px")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return stacked_px(a, b, k); };
  else throw std::invalid_argument("unknown predicate '" + p + "'");
  return [f, con, clamp01](const std::vector<const Segment*>& parts, const Context& ctx) {
    if (parts.size() < 2) throw std::invalid_argument("predicate '" + con->predicate + "' needs two parts");
    return clamp01(f(*parts[0], *parts[1], *con, ctx));
  };
}

double evaluate(const Constraint& c, const std::vector<const Segment*>& parts, const Context& ctx) {
  return compile(c)(parts, ctx);
}

double surface_distance(const Segment& s, const Eigen::Vector3d& p) { return s.surface_distance(p); }

double extent(const Segment& s) { return s.extent(); }

}  // namespace mereo::knowledge
