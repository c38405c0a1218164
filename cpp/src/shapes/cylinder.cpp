#include "mereo/shapes/cylinder.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

double Cylinder::extent() const { return std::hypot(radius, height / 2); }

double Cylinder::half_extent_along(const Eigen::Vector3d& dir) const {
  const double c = std::abs(axis.normalized().dot(dir));
  const double sn = std::sqrt(std::max(0.0, 1 - c * c));
  return c * height / 2 + sn * radius;
}

double Cylinder::surface_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d q = p - point;
  const double along = a.dot(q);
  const double radial = (q - a * along).norm() - radius;
  const double axial = std::abs(along) - height / 2;
  return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
}

std::optional<Cylinder> Cylinder::from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&) {
  Eigen::Vector3d a = n[0].cross(n[1]);
  const double sn = a.norm();
  if (sn < 0.05) return std::nullopt;  // nearly parallel normals: no axis
  a /= sn;
  // in the plane orthogonal to the axis, the normal lines meet at the axis
  const Eigen::Vector3d m1 = n[0] - a * a.dot(n[0]), m2 = n[1] - a * a.dot(n[1]);
  const Eigen::Vector3d q1 = p[0] - a * a.dot(p[0]), q2 = p[1] - a * a.dot(p[1]);
  const Eigen::Vector3d w = q1 - q2;
  const double A = m1.dot(m1), b = m1.dot(m2), c = m2.dot(m2), d = m1.dot(w), e = m2.dot(w);
  const double den = A * c - b * b;
  if (std::abs(den) < 1e-9) return std::nullopt;
  const double t = (b * e - c * d) / den, u = (A * e - b * d) / den;
  const Eigen::Vector3d c1 = q1 + t * m1, c2 = q2 + u * m2;
  Cylinder s;
  s.axis = a;
  s.point = 0.5 * (c1 + c2) + a * a.dot(p[0]);
  s.radius = 0.5 * ((q1 - c1).norm() + (q2 - c2).norm());
  return s;
}

Eigen::VectorXd Cylinder::pack() const {
  Eigen::VectorXd v(7);
  v << point, axis, radius;
  return v;
}

void Cylinder::unpack(const Eigen::VectorXd& v) {
  point = v.head<3>();
  axis = v.segment<3>(3).normalized();
  radius = v(6);
}

double Cylinder::range_residual(const Eigen::Vector3d& x) const {
  return ray_residual(x, point, &axis, radius);
}

double Cylinder::range_residual(const Eigen::Vector3d& x, const Eigen::VectorXd& packed, double* grad) const {
  return ray_residual(x, point, &axis, radius, packed.segment<3>(3).norm(), grad);
}

void Cylinder::set_extent(const std::vector<Eigen::Vector3d>& points) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : points) {
    const double t = axis.dot(p - point);
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  point += axis * (0.5 * (lo + hi));
  height = hi - lo;
}

void Cylinder::fields(FieldList& out, bool inward) const {
  out.push_back({"point", point});
  out.push_back({"axis", axis});
  out.push_back({"radius", radius});
  out.push_back({"height", height});
  out.push_back({"inward", inward});
}

bool Cylinder::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "point" || key == "center") && vector3(v)) return point = *vector3(v), true;
  if (key == "axis" && vector3(v)) return axis = vector3(v)->normalized(), true;
  if (key == "radius" && number(v)) return radius = *number(v), true;
  if (key == "height" && number(v)) return height = *number(v), true;
  return false;
}

std::optional<double> Cylinder::attribute(const std::string& key) const {
  if (key == "radius") return radius;
  if (key == "height") return height;
  if (key == "aspect") return radius > 0 ? height / (2 * radius) : NAN;
  return std::nullopt;
}

void Cylinder::outline(Outline& out) const { frustum_outline(point, axis, height, radius, radius, out); }

void Cylinder::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(point(i), false);
  t.add(radius, true);
  t.add(height, false);
}

}  // namespace mereo::shapes
