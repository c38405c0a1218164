#include "mereo/shapes/plane.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace mereo::shapes {

double Plane::surface_distance(const Eigen::Vector3d& x) const { return std::abs(normal.normalized().dot(x) + d); }

std::optional<Plane> Plane::from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&) {
  Plane s;
  s.normal = n[0].normalized();
  s.d = -s.normal.dot(p[0]);
  s.point = p[0];
  return s;
}

bool Plane::fit_direct(const std::vector<Eigen::Vector3d>& points) {
  // the normal of least scatter (PCA), keeping the side of the start
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p;
  c /= double(points.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& p : points) C += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  Eigen::Vector3d n = es.eigenvectors().col(0);
  if (n.dot(normal) < 0) n = -n;
  normal = n, d = -n.dot(c), point = c;
  return true;
}

void Plane::set_extent(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p;
  point = c / double(points.size());
}

void Plane::canonical() {
  if (normal.dot(point) > 0) normal = -normal, d = -d;  // towards the camera
}

void Plane::transform(const Eigen::Isometry3d& T) {
  point = T * point;
  normal = T.linear() * normal;
  d = -normal.dot(point);
}

void Plane::fields(FieldList& out, bool) const {
  out.push_back({"normal", normal});
  out.push_back({"d", d});
  out.push_back({"point", point});
}

bool Plane::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "normal" || key == "axis") && vector3(v)) return normal = vector3(v)->normalized(), true;
  if (key == "point" && vector3(v)) return point = *vector3(v), true;
  if (key == "d" && number(v)) return d = *number(v), true;
  return false;
}

std::optional<double> Plane::attribute(const std::string& key) const {
  if (key == "d") return d;
  return std::nullopt;
}

}  // namespace mereo::shapes
