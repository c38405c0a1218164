#include "mereo/shapes/region.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

void Region::frame(Eigen::Vector3d e[3], double half[3]) const {
  e[2] = axis.normalized();
  e[0] = unit_across(width_axis, e[2]);
  e[1] = e[2].cross(e[0]);
  half[0] = width / 2, half[1] = thickness / 2, half[2] = height / 2;
}

double Region::half_extent_along(const Eigen::Vector3d& dir) const {
  Eigen::Vector3d e[3];
  double h[3];
  frame(e, h);
  return std::abs(e[0].dot(dir)) * h[0] + std::abs(e[1].dot(dir)) * h[1] + std::abs(e[2].dot(dir)) * h[2];
}

double Region::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  if (n) *n = axis.normalized();
  return surface_distance(x);
}

double Region::surface_distance(const Eigen::Vector3d& x) const {
  Eigen::Vector3d e[3];
  double h[3];
  frame(e, h);
  const Eigen::Vector3d q = x - point;
  double out = 0;
  for (int k = 0; k < 3; ++k) out += std::pow(std::max(0.0, std::abs(e[k].dot(q)) - h[k]), 2);
  return std::sqrt(out);  // 0 inside: a region is the solid box that holds it
}

void Region::fields(FieldList& out, bool) const {
  out.push_back({"point", point});
  out.push_back({"axis", axis});
  out.push_back({"width_axis", width_axis});
  out.push_back({"width", width});
  out.push_back({"thickness", thickness});
  out.push_back({"height", height});
  out.push_back({"foot", foot});
  out.push_back({"neck", neck});
}

bool Region::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "point" || key == "center") && vector3(v)) return point = *vector3(v), true;
  if (key == "axis" && vector3(v)) return axis = vector3(v)->normalized(), true;
  if (key == "width_axis" && vector3(v)) return width_axis = vector3(v)->normalized(), true;
  if (key == "width" && number(v)) return width = *number(v), true;
  if (key == "thickness" && number(v)) return thickness = *number(v), true;
  if (key == "height" && number(v)) return height = *number(v), true;
  if (key == "foot" && number(v)) return foot = *number(v), true;
  if (key == "neck" && number(v)) return neck = *number(v), true;
  return false;
}

std::optional<double> Region::attribute(const std::string& key) const {
  if (key == "width") return width;
  if (key == "thickness") return thickness;
  if (key == "height") return height;
  if (key == "foot") return foot;
  if (key == "neck") return neck;
  if (key == "slenderness") return height / std::max(width, 1e-6);  // tall and narrow: > 1
  return std::nullopt;
}

void Region::outline(Outline& out) const {
  Eigen::Vector3d e[3];
  double h[3];
  frame(e, h);
  const auto corner = [&](int i) {  // bit 0: width, bit 1: depth, bit 2: up
    return Eigen::Vector3d(point + (i & 1 ? h[0] : -h[0]) * e[0] + (i & 2 ? h[1] : -h[1]) * e[1] +
                           (i & 4 ? h[2] : -h[2]) * e[2]);
  };
  for (int z : {0, 4}) out.lines.push_back({corner(z), corner(z | 1), corner(z | 3), corner(z | 2), corner(z)});
  for (int c = 0; c < 4; ++c) out.lines.push_back({corner(c), corner(c | 4)});
  if (!out.anchor) out.anchor = corner(e[2].dot(-Eigen::Vector3d::UnitY()) >= 0 ? 4 : 0);
}

void Region::set_direction(const Eigen::Vector3d& d) {
  axis = d.normalized();
  width_axis = unit_across(width_axis, axis);
}

void Region::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(point(i), false);
  t.add(width, false), t.add(thickness, false), t.add(height, false);
}

}  // namespace mereo::shapes
