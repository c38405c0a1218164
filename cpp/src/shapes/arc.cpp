#include "mereo/shapes/arc.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

double Arc::half_extent_along(const Eigen::Vector3d& dir) const {
  const double c = std::abs(normal.normalized().dot(dir));
  return std::sqrt(std::max(0.0, 1 - c * c)) * radius;
}

double Arc::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  if (n) *n = Eigen::Vector3d::UnitZ();
  return surface_distance(x);
}

double Arc::surface_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = normal.normalized();
  const Eigen::Vector3d q = p - center;
  const double h = a.dot(q);
  const double rho = (q - a * h).norm();
  return std::max(0.0, std::hypot(rho - radius, h));
}

void Arc::fields(FieldList& out, bool) const {
  out.push_back({"center", center});
  out.push_back({"normal", normal});
  out.push_back({"radius", radius});
}

bool Arc::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "center" || key == "point") && vector3(v)) return center = *vector3(v), true;
  if ((key == "normal" || key == "axis") && vector3(v)) return normal = vector3(v)->normalized(), true;
  if (key == "radius" && number(v)) return radius = *number(v), true;
  return false;
}

std::optional<double> Arc::attribute(const std::string& key) const {
  if (key == "radius") return radius;
  return std::nullopt;
}

void Arc::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(center(i), false);
  t.add(radius, true);
}

}  // namespace mereo::shapes
