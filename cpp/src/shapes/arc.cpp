#include "mereo/shapes/arc.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

Eigen::Vector2d Arc::at(double t_deg) const {
  const double t = t_deg * M_PI / 180, a = angle_deg * M_PI / 180;
  const Eigen::Vector2d e(axes_px.x() * std::cos(t), axes_px.y() * std::sin(t));
  return center_px + Eigen::Vector2d(std::cos(a) * e.x() - std::sin(a) * e.y(), std::sin(a) * e.x() + std::cos(a) * e.y());
}

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
  out.push_back({"center_px", center_px});
  out.push_back({"axes_px", axes_px});
  out.push_back({"angle_deg", angle_deg});
  out.push_back({"start_deg", start_deg});
  out.push_back({"end_deg", end_deg});
  out.push_back({"contrast", sides.contrast()});
  out.push_back({"color_inside", sides.a});
  out.push_back({"color_outside", sides.b});
  if (!lifted) return;
  out.push_back({"center", center});
  out.push_back({"normal", normal});
  out.push_back({"radius", radius});
}

bool Arc::set_field(const std::string& key, const FieldValue& v) {
  if (key == "center_px" && vector2(v)) return center_px = *vector2(v), true;
  if (key == "axes_px" && vector2(v)) return axes_px = *vector2(v), true;
  if (key == "angle_deg" && number(v)) return angle_deg = *number(v), true;
  if (key == "start_deg" && number(v)) return start_deg = *number(v), true;
  if (key == "end_deg" && number(v)) return end_deg = *number(v), true;
  if (key == "color_inside" && vector3(v)) return sides.a = *vector3(v), true;
  if (key == "color_outside" && vector3(v)) return sides.b = *vector3(v), true;
  if (key == "contrast" && number(v)) return true;  // derived from the colours
  if ((key == "center" || key == "point") && vector3(v)) return center = *vector3(v), lifted = true;
  if ((key == "normal" || key == "axis") && vector3(v)) return normal = vector3(v)->normalized(), lifted = true;
  if (key == "radius" && number(v)) return radius = *number(v), lifted = true;
  return false;
}

std::optional<double> Arc::attribute(const std::string& key) const {
  if (key == "radius" && lifted) return radius;
  if (key == "major_px") return axes_px.x();
  if (key == "span_deg") return span_deg();
  if (key == "contrast") return sides.contrast();
  return std::nullopt;
}

void Arc::outline(Outline& out) const {
  if (axes_px.x() > 0 && span_deg() > 0) {  // as seen
    const int n = std::clamp(int(span_deg() / 5) + 1, 2, 73);
    std::vector<Eigen::Vector2d> l;
    for (int k = 0; k <= n; ++k) l.push_back(at(start_deg + span_deg() * k / n));
    return out.pixels.push_back(std::move(l));
  }
  if (lifted) out.lines.push_back(circle(center, normal, radius));
}

void Arc::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(center(i), false);
  t.add(radius, true);
}

}  // namespace mereo::shapes
