#include "mereo/shapes/line.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

double Line::half_extent_along(const Eigen::Vector3d& dir) const {
  return std::abs(axis.normalized().dot(dir)) * length / 2;
}

double Line::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  if (n) *n = Eigen::Vector3d::UnitZ();
  return surface_distance(x);
}

double Line::surface_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = axis.normalized();
  const double t = std::clamp(a.dot(p - point), -length / 2, length / 2);
  return (p - (point + a * t)).norm();
}

void Line::fields(FieldList& out, bool) const {
  out.push_back({"start_px", start_px});
  out.push_back({"end_px", end_px});
  out.push_back({"contrast", sides.contrast()});
  out.push_back({"color_left", sides.a});
  out.push_back({"color_right", sides.b});
  if (!lifted) return;
  out.push_back({"point", point});
  out.push_back({"axis", axis});
  out.push_back({"length", length});
}

bool Line::set_field(const std::string& key, const FieldValue& v) {
  if (key == "start_px" && vector2(v)) return start_px = *vector2(v), true;
  if (key == "end_px" && vector2(v)) return end_px = *vector2(v), true;
  if (key == "color_left" && vector3(v)) return sides.a = *vector3(v), true;
  if (key == "color_right" && vector3(v)) return sides.b = *vector3(v), true;
  if (key == "contrast" && number(v)) return true;  // derived from the colours
  if ((key == "point" || key == "center") && vector3(v)) return point = *vector3(v), lifted = true;
  if (key == "axis" && vector3(v)) return axis = vector3(v)->normalized(), lifted = true;
  if ((key == "length" || key == "height") && number(v)) return length = *number(v), lifted = true;
  return false;
}

std::optional<double> Line::attribute(const std::string& key) const {
  if ((key == "length" || key == "height") && lifted) return length;
  if (key == "length_px") return length_px();
  if (key == "contrast") return sides.contrast();
  return std::nullopt;
}

void Line::outline(Outline& out) const {
  if (length_px() > 0) return out.pixels.push_back({start_px, end_px});  // as seen
  if (!lifted) return;
  const Eigen::Vector3d a = axis.normalized() * (length / 2);
  out.lines.push_back({point - a, point + a});
}

void Line::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(point(i), false);
  t.add(length, false);
}

}  // namespace mereo::shapes
