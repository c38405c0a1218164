#include "mereo/shapes/sphere.hpp"

#include <cmath>

#include "mereo/shapes/cylinder.hpp"  // ray_residual

namespace mereo::shapes {

double Sphere::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  const Eigen::Vector3d q = x - center;
  const double l = q.norm();
  if (n) *n = l > 0 ? Eigen::Vector3d(q / l) : Eigen::Vector3d::UnitZ();
  return l - radius;
}

double Sphere::surface_distance(const Eigen::Vector3d& p) const { return std::max(0.0, (p - center).norm() - radius); }

std::optional<Sphere> Sphere::from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&) {
  // closest points of the lines p1 + t n1 and p2 + u n2
  const Eigen::Vector3d w = p[0] - p[1];
  const double a = n[0].dot(n[0]), b = n[0].dot(n[1]), c = n[1].dot(n[1]), d = n[0].dot(w), e = n[1].dot(w);
  const double den = a * c - b * b;
  if (std::abs(den) < 1e-6) return std::nullopt;
  const double t = (b * e - c * d) / den, u = (a * e - b * d) / den;
  const Eigen::Vector3d c1 = p[0] + t * n[0], c2 = p[1] + u * n[1];
  if ((c1 - c2).norm() > 0.25 * (std::abs(t) + std::abs(u)) + 1e-3) return std::nullopt;  // normals miss
  Sphere s;
  s.center = 0.5 * (c1 + c2);
  s.radius = 0.5 * ((p[0] - s.center).norm() + (p[1] - s.center).norm());
  return s;
}

Eigen::VectorXd Sphere::pack() const {
  Eigen::VectorXd v(4);
  v << center, radius;
  return v;
}

double Sphere::range_residual(const Eigen::Vector3d& x) const {
  return ray_residual(x, center, nullptr, radius);
}

double Sphere::range_residual(const Eigen::Vector3d& x, const Eigen::VectorXd&, double* grad) const {
  return ray_residual(x, center, nullptr, radius, 1.0, grad);
}

void Sphere::set_extent(const std::vector<Eigen::Vector3d>& inliers) {
  cap.setZero();
  for (const auto& p : inliers)
    if ((p - center).norm() > 0) cap += (p - center).normalized();
  if (!inliers.empty()) cap /= double(inliers.size());
}

void Sphere::fields(FieldList& out, bool inward) const {
  out.push_back({"center", center});
  out.push_back({"radius", radius});
  out.push_back({"inward", inward});
  out.push_back({"cap", cap});
}

bool Sphere::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "center" || key == "point") && vector3(v)) return center = *vector3(v), true;
  if (key == "radius" && number(v)) return radius = *number(v), true;
  if (key == "cap" && vector3(v)) return cap = *vector3(v), true;
  return false;
}

std::optional<double> Sphere::attribute(const std::string& key) const {
  if (key == "radius") return radius;
  return std::nullopt;
}

void Sphere::outline(Outline& out) const {
  out.lines.push_back(circle(center, center, radius));  // the outline facing the camera
  if (!out.anchor) out.anchor = Eigen::Vector3d(center - radius * Eigen::Vector3d::UnitY());
}

void Sphere::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(center(i), false);
  t.add(radius, true);
}

}  // namespace mereo::shapes
