#include "mereo/shapes/cone.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <Eigen/Dense>

namespace mereo::shapes {

double Cone::extent() const {
  return std::hypot(std::max(radius_at(-0.5 * height), radius_at(0.5 * height)), height / 2);
}

double Cone::half_extent_along(const Eigen::Vector3d& dir) const {
  const double c = std::abs(axis.normalized().dot(dir));
  const double sn = std::sqrt(std::max(0.0, 1 - c * c));
  return c * height / 2 + sn * std::max(radius_at(-0.5 * height), radius_at(0.5 * height));
}

double Cone::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  // in the plane of the axis and x: (t along the axis from `point`, rho from the axis); the
  // surface is the line rho = radius + tan(angle) t, whose outward unit normal is
  // (-sin angle, cos angle)
  // The unit axis and the angle's cosine and sine are kept per thread for the last cone seen:
  // the loops over a segment's pixels and a refit's points ask of one cone hundreds of times in
  // a row. They are reused only for the same bits of axis and angle, so the results are those
  // computed afresh.
  thread_local Eigen::Vector3d last_axis(NAN, NAN, NAN), a(NAN, NAN, NAN);
  thread_local double last_angle = NAN, c = NAN, s = NAN;
  if (std::memcmp(axis.data(), last_axis.data(), sizeof(double) * 3) != 0) last_axis = axis, a = axis.normalized();
  if (std::memcmp(&angle, &last_angle, sizeof(double)) != 0) last_angle = angle, c = std::cos(angle), s = std::sin(angle);
  const Eigen::Vector3d q = x - point;
  const double t = a.dot(q);
  const Eigen::Vector3d radial = q - a * t;
  const double rho = radial.norm();
  const Eigen::Vector3d u = rho > 0 ? Eigen::Vector3d(radial / rho) : Eigen::Vector3d(a.unitOrthogonal());
  if (n) *n = c * u - s * a;
  return (rho - radius) * c - t * s;
}

double Cone::surface_distance(const Eigen::Vector3d& x) const {
  // distance to the solid frustum, in the (t, rho) half-plane: the trapezoid with corners
  // (-h/2, 0), (-h/2, r0), (h/2, r1), (h/2, 0)
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d q = x - point;
  const double t = a.dot(q), rho = (q - a * t).norm(), h = height / 2;
  const double r0 = radius_at(-h), r1 = radius_at(h);
  const double slant = signed_distance(x);
  if (std::abs(t) <= h && slant <= 0) return 0.0;  // inside
  auto seg = [&](double t0, double p0, double t1, double p1) {
    const Eigen::Vector2d A(t0, p0), B(t1, p1), P(t, rho);
    const double len2 = (B - A).squaredNorm();
    const double k = len2 > 0 ? std::clamp((P - A).dot(B - A) / len2, 0.0, 1.0) : 0.0;
    return (P - (A + k * (B - A))).norm();
  };
  return std::min({seg(-h, 0, -h, r0), seg(-h, r0, h, r1), seg(h, r1, h, 0)});
}

std::optional<Cone> Cone::from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits& l) {
  // the apex: n_i . x = n_i . p_i for the three tangent planes
  Eigen::Matrix3d A;
  Eigen::Vector3d b;
  for (int i = 0; i < 3; ++i) A.row(i) = n[i].transpose(), b(i) = n[i].dot(p[i]);
  Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
  if (lu.rank() < 3 || std::abs(A.determinant()) < 1e-6) return std::nullopt;
  const Eigen::Vector3d apex = lu.solve(b);
  // the axis: normal to the plane through apex + unit directions to the points
  Eigen::Vector3d d[3];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d v = p[i] - apex;
    if (v.norm() < 1e-6) return std::nullopt;
    d[i] = v.normalized();
  }
  Eigen::Vector3d a = (d[1] - d[0]).cross(d[2] - d[0]);
  if (a.norm() < 1e-9) return std::nullopt;
  a.normalize();
  if (a.dot(d[0]) < 0) a = -a;  // towards the points: the way the cone widens
  double ang = 0;
  for (int i = 0; i < 3; ++i) ang += std::acos(std::clamp(a.dot(d[i]), -1.0, 1.0)) / 3;
  if (!(ang >= kMinAngle && ang <= kMaxAngle)) return std::nullopt;
  Cone c;
  c.axis = a, c.angle = ang;
  // placed at the first point's height along the axis
  const double t0 = a.dot(p[0] - apex);
  c.point = apex + a * t0;
  c.radius = t0 * std::tan(ang);
  if (!(c.radius > 0) || c.radius > 2 * l.max_radius) return std::nullopt;
  return c;
}

Eigen::VectorXd Cone::pack() const {
  Eigen::VectorXd v(8);
  v << point, axis, radius, angle;
  return v;
}

void Cone::unpack(const Eigen::VectorXd& v) {
  point = v.head<3>();
  axis = v.segment<3>(3).normalized();
  radius = v(6);
  angle = v(7);
}

void Cone::set_extent(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Vector3d a = axis.normalized();
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : points) {
    const double t = a.dot(p - point);
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  const double mid = 0.5 * (lo + hi);
  radius = radius_at(mid);
  point += a * mid;
  height = hi - lo;
}

void Cone::canonical() {
  if (angle < 0) axis = -axis, angle = -angle;  // the axis points the way the cone widens
}

void Cone::fields(FieldList& out, bool inward) const {
  out.push_back({"point", point});
  out.push_back({"axis", axis});
  out.push_back({"radius", radius});
  out.push_back({"half_angle_deg", angle * 180 / M_PI});
  out.push_back({"height", height});
  out.push_back({"radius_narrow", radius_at(-0.5 * height)});
  out.push_back({"radius_wide", radius_at(0.5 * height)});
  out.push_back({"inward", inward});
}

bool Cone::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "point" || key == "center") && vector3(v)) return point = *vector3(v), true;
  if (key == "axis" && vector3(v)) return axis = vector3(v)->normalized(), true;
  if (key == "radius" && number(v)) return radius = *number(v), true;
  if (key == "height" && number(v)) return height = *number(v), true;
  if (key == "half_angle_deg" && number(v)) return angle = *number(v) * M_PI / 180, true;
  if (key == "radius_narrow" || key == "radius_wide") return number(v).has_value();  // derived
  return false;
}

std::optional<double> Cone::attribute(const std::string& key) const {
  if (key == "radius") return radius;
  if (key == "height") return height;
  if (key == "aspect") return radius > 0 ? height / (2 * radius) : NAN;
  if (key == "half_angle_deg") return angle * 180 / M_PI;
  if (key == "radius_narrow") return radius_at(-0.5 * height);
  if (key == "radius_wide") return radius_at(0.5 * height);
  return std::nullopt;
}

void Cone::outline(Outline& out) const {
  frustum_outline(point, axis, height, radius_at(-0.5 * height), radius_at(0.5 * height), out);
}

void Cone::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(point(i), false);
  t.add(radius, false);  // at the middle of the visible extent: it moves with the view
  t.add(angle, true);
  t.add(height, false);
}

}  // namespace mereo::shapes
