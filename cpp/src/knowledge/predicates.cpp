// The built-in fuzzy predicates and attributes of object models (see predicates.hpp).
#include "mereo/knowledge/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
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
/// The condition x >= 0 as a ramp of width 2 * tol centred on 0.
double ramp(double x, double tol) { return std::clamp((x + tol) / (2 * tol), 0.0, 1.0); }

bool has_axis(PrimitiveClass c) { return c != PrimitiveClass::Sphere; }

/// Angle in [0, 90] degrees between two undirected axes.
double axis_angle(const Segment& a, const Segment& b) {
  const double c = std::abs(a.axis.normalized().dot(b.axis.normalized()));
  return std::acos(std::min(1.0, c)) / kDeg;
}

double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& point, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d q = p - point;
  return (q - a * a.dot(q)).norm();
}

/// Half extent of s along the unit direction `dir` (for "on": lowest and highest points).
double half_extent_along(const Segment& s, const Eigen::Vector3d& dir) {
  const double c = std::abs(s.axis.normalized().dot(dir));
  const double sn = std::sqrt(std::max(0.0, 1 - c * c));
  switch (s.cls) {
    case PrimitiveClass::Cylinder: return c * s.height / 2 + sn * s.radius;
    case PrimitiveClass::Torus: return sn * (s.radius + s.minor_radius) + c * s.minor_radius;
    case PrimitiveClass::Sphere: return s.radius;
    case PrimitiveClass::Line: return c * s.height / 2;
    case PrimitiveClass::Arc: return sn * s.radius;
    case PrimitiveClass::Plane: return 0.0;
  }
  return 0.0;
}

double size_of(const Segment& s) { return s.cls == PrimitiveClass::Line ? s.height : s.radius; }

double param(const Constraint& c, const char* name, double fallback) { return c.param(name, fallback); }

double near(const Segment& a, const Segment& b, const Constraint& c) {
  const double gap = std::max(surface_distance(a, b.point) - extent(b), surface_distance(b, a.point) - extent(a));
  return falling(gap, 0.0, param(c, "max", 0.01));
}

/// The handle-on-body function: a torus (handle) and a cylinder (body).
double handle_on_body(const Segment& torus, const Segment& body, double tol) {
  const Eigen::Vector3d axis = body.axis.normalized();
  const Eigen::Vector3d q = torus.point - body.point;
  const double along = axis.dot(q);
  const double d = (q - axis * along).norm();
  const double inner_inside = ramp(body.radius - (d - torus.radius), tol);  // d - R < r_body
  const double outer_outside = ramp((d + torus.radius) - body.radius, tol);  // d + R > r_body
  const double within_height = ramp(body.height / 2 - std::abs(along), tol);
  return std::min({inner_inside, outer_outside, within_height});
}

double intersects(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance", 0.003);
  if (a.cls == PrimitiveClass::Torus && b.cls == PrimitiveClass::Cylinder) return handle_on_body(a, b, tol);
  if (a.cls == PrimitiveClass::Cylinder && b.cls == PrimitiveClass::Torus) return handle_on_body(b, a, tol);
  return ramp(extent(b) - surface_distance(a, b.point), tol);
}

double parallel(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance_deg", 10.0);
  return falling(axis_angle(a, b), tol, 2 * tol);
}
double perpendicular(const Segment& a, const Segment& b, const Constraint& c) {
  const double tol = param(c, "tolerance_deg", 10.0);
  return falling(90.0 - axis_angle(a, b), tol, 2 * tol);
}
double coaxial(const Segment& a, const Segment& b, const Constraint& c) {
  const double dist = param(c, "distance", 0.01);
  return std::min(parallel(a, b, c), falling(distance_to_line(b.point, a.point, a.axis), dist, 2 * dist));
}
double above(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double margin = param(c, "margin", 0.01);
  const double h = ctx.up.normalized().dot(a.point - b.point);
  return std::clamp(h / margin, 0.0, 1.0);
}
double on(const Segment& a, const Segment& b, const Constraint& c, const Context& ctx) {
  const double tol = param(c, "tolerance", 0.01);
  const Eigen::Vector3d up = ctx.up.normalized();
  const double low_a = up.dot(a.point) - half_extent_along(a, up);
  const double top_b = b.cls == PrimitiveClass::Plane ? -b.d * up.dot(b.axis) : up.dot(b.point) + half_extent_along(b, up);
  const double contact = falling(std::abs(low_a - top_b), tol, 2 * tol);
  if (b.cls == PrimitiveClass::Plane) return contact;
  const Eigen::Vector3d dh = (a.point - b.point) - up * up.dot(a.point - b.point);
  const double reach = extent(b);
  return std::min(contact, falling(dh.norm(), reach, reach + tol));
}
double same_size(const Segment& a, const Segment& b, const Constraint& c) {
  const double ratio = param(c, "ratio", 0.8);
  const double sa = size_of(a), sb = size_of(b);
  if (!(sa > 0) || !(sb > 0)) return 0.0;
  const double q = std::min(sa, sb) / std::max(sa, sb);
  return std::clamp((q - (ratio - 0.2)) / 0.2, 0.0, 1.0);
}
double distance(const Segment& a, const Segment& b, const Constraint& c) {
  const double margin = param(c, "margin", 0.01);
  const double lo = param(c, "min", 0.0), hi = param(c, "max", 1e300);
  return Membership::range(lo, hi, margin)((a.point - b.point).norm());
}

const std::map<std::string, std::vector<std::string>>& predicate_table() {
  static const std::map<std::string, std::vector<std::string>> t = {
      {"near", {"max"}},
      {"intersects", {"tolerance"}},
      {"parallel", {"tolerance_deg"}},
      {"perpendicular", {"tolerance_deg"}},
      {"coaxial", {"tolerance_deg", "distance"}},
      {"above", {"margin"}},
      {"on", {"tolerance"}},
      {"same_size", {"ratio"}},
      {"distance", {"min", "max", "margin"}},
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
  static const std::vector<std::string> names = {"radius", "height",   "minor_radius", "aspect",
                                                 "tilt_deg", "elevation", "inliers",     "residual",
                                                 "hue",    "d",         "inward"};
  return names;
}
bool is_attribute(const std::string& name) {
  const auto& n = attribute_names();
  return std::find(n.begin(), n.end(), name) != n.end();
}

double attribute_value(const Segment& s, const std::string& name, const Context& ctx) {
  if (name == "radius") return s.radius;
  if (name == "height") return s.height;
  if (name == "minor_radius") return s.minor_radius;
  if (name == "aspect") return s.radius > 0 ? s.height / (2 * s.radius) : NAN;
  if (name == "tilt_deg") {
    const double c = std::abs(s.axis.normalized().dot(ctx.up.normalized()));
    return std::acos(std::min(1.0, c)) / kDeg;
  }
  if (name == "elevation") return ctx.up.normalized().dot(s.point);
  if (name == "inliers") return double(s.inliers);
  if (name == "residual") return s.residual;
  if (name == "hue") return s.hue;
  if (name == "d") return s.d;
  if (name == "inward") return s.inward ? 1.0 : 0.0;
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
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return intersects(a, b, k); };
  else if (p == "parallel")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a.cls) && has_axis(b.cls) ? parallel(a, b, k) : 0.0;
    };
  else if (p == "perpendicular")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a.cls) && has_axis(b.cls) ? perpendicular(a, b, k) : 0.0;
    };
  else if (p == "coaxial")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) {
      return has_axis(a.cls) && has_axis(b.cls) ? coaxial(a, b, k) : 0.0;
    };
  else if (p == "above") f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return above(a, b, k, x); };
  else if (p == "on") f = [](const Segment& a, const Segment& b, const Constraint& k, const Context& x) { return on(a, b, k, x); };
  else if (p == "same_size")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return same_size(a, b, k); };
  else if (p == "distance")
    f = [](const Segment& a, const Segment& b, const Constraint& k, const Context&) { return distance(a, b, k); };
  else throw std::invalid_argument("unknown predicate '" + p + "'");
  return [f, con, clamp01](const std::vector<const Segment*>& parts, const Context& ctx) {
    if (parts.size() < 2) throw std::invalid_argument("predicate '" + con->predicate + "' needs two parts");
    return clamp01(f(*parts[0], *parts[1], *con, ctx));
  };
}

double evaluate(const Constraint& c, const std::vector<const Segment*>& parts, const Context& ctx) {
  return compile(c)(parts, ctx);
}

double surface_distance(const Segment& s, const Eigen::Vector3d& p) {
  switch (s.cls) {
    case PrimitiveClass::Plane: return std::abs(s.axis.normalized().dot(p) + s.d);
    case PrimitiveClass::Cylinder: {
      const Eigen::Vector3d a = s.axis.normalized();
      const Eigen::Vector3d q = p - s.point;
      const double along = a.dot(q);
      const double radial = (q - a * along).norm() - s.radius;
      const double axial = std::abs(along) - s.height / 2;
      return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
    }
    case PrimitiveClass::Torus:
    case PrimitiveClass::Arc: {
      const Eigen::Vector3d n = s.axis.normalized();
      const Eigen::Vector3d q = p - s.point;
      const double h = n.dot(q);
      const double rho = (q - n * h).norm();
      const double tube = s.cls == PrimitiveClass::Torus ? s.minor_radius : 0.0;
      return std::max(0.0, std::hypot(rho - s.radius, h) - tube);
    }
    case PrimitiveClass::Sphere: return std::max(0.0, (p - s.point).norm() - s.radius);
    case PrimitiveClass::Line: {
      const Eigen::Vector3d a = s.axis.normalized();
      const double t = std::clamp(a.dot(p - s.point), -s.height / 2, s.height / 2);
      return (p - (s.point + a * t)).norm();
    }
  }
  return INFINITY;
}

double extent(const Segment& s) {
  switch (s.cls) {
    case PrimitiveClass::Cylinder: return std::hypot(s.radius, s.height / 2);
    case PrimitiveClass::Torus: return s.radius + s.minor_radius;
    case PrimitiveClass::Sphere: return s.radius;
    case PrimitiveClass::Line: return s.height / 2;
    case PrimitiveClass::Arc: return s.radius;
    case PrimitiveClass::Plane: return 0.0;
  }
  return 0.0;
}

}  // namespace mereo::knowledge
