#include "mereo/shapes/patch.hpp"

#include <algorithm>
#include <cmath>

namespace mereo::shapes {

double Patch::surface_distance(const Eigen::Vector3d& x) const {
  const Eigen::Vector3d q = x - point;
  const double du = std::max(0.0, std::abs(u_axis.dot(q)) - size_u / 2);
  const double dv = std::max(0.0, std::abs(v_axis().dot(q)) - size_v / 2);
  const double dn = normal.normalized().dot(q);
  return std::sqrt(du * du + dv * dv + dn * dn);
}

void Patch::fields(FieldList& out, bool) const {
  out.push_back({"point", point});
  out.push_back({"normal", normal});
  out.push_back({"u_axis", u_axis});
  out.push_back({"size_u", size_u});
  out.push_back({"size_v", size_v});
  out.push_back({"area", area});
  if (std::isfinite(open_below)) out.push_back({"open_below", open_below});
  out.push_back({"top_hidden", top_hidden});
  out.push_back({"bottom_hidden", bottom_hidden});
  out.push_back({"far_hidden", far_hidden});
  out.push_back({"flush", flush});
  out.push_back({"side_cut", side_cut});
  if (std::isfinite(stands_out)) out.push_back({"stands_out", stands_out});
}

bool Patch::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "point" || key == "center") && vector3(v)) return point = *vector3(v), true;
  if ((key == "normal" || key == "axis") && vector3(v)) return set_direction(*vector3(v)), true;
  if (key == "u_axis" && vector3(v)) return u_axis = unit_across(*vector3(v), normal.normalized()), true;
  if (key == "size_u" && number(v)) return size_u = *number(v), true;
  if (key == "size_v" && number(v)) return size_v = *number(v), true;
  if (key == "area" && number(v)) return area = *number(v), true;
  if (key == "open_below" && number(v)) return open_below = *number(v), true;
  if (key == "side_cut" && number(v)) return side_cut = *number(v), true;
  if (key == "stands_out" && number(v)) return stands_out = *number(v), true;
  if (key == "top_hidden" || key == "bottom_hidden" || key == "far_hidden" || key == "flush") {
    const bool* b = std::get_if<bool>(&v);
    if (!b && !number(v)) return false;
    (key == "top_hidden"      ? top_hidden
     : key == "bottom_hidden" ? bottom_hidden
     : key == "far_hidden"    ? far_hidden
                              : flush) = b ? *b : *number(v) != 0;
    return true;
  }
  return false;
}

std::optional<double> Patch::attribute(const std::string& key) const {
  if (key == "length") return std::max(size_u, size_v);
  if (key == "width") return std::min(size_u, size_v);
  if (key == "area") return area;
  if (key == "side_cut") return side_cut;
  if (key == "open_below") return std::isfinite(open_below) ? std::optional<double>(open_below) : std::nullopt;
  if (key == "top_hidden") return top_hidden ? 1.0 : 0.0;
  if (key == "bottom_hidden") return bottom_hidden ? 1.0 : 0.0;
  if (key == "far_hidden") return far_hidden ? 1.0 : 0.0;
  if (key == "flush") return flush ? 1.0 : 0.0;
  if (key == "view_deg" && point.norm() > 0)
    return std::acos(std::min(1.0, std::abs(normal.normalized().dot(point.normalized())))) * 180.0 / M_PI;
  if (key == "stands_out") return std::isfinite(stands_out) ? std::optional<double>(stands_out) : std::nullopt;
  return std::nullopt;
}

void Patch::outline(Outline& out) const {
  const Eigen::Vector3d u = u_axis * (size_u / 2), v = v_axis() * (size_v / 2);
  out.lines.push_back({point - u - v, point + u - v, point + u + v, point - u + v, point - u - v});
  if (!out.anchor) {  // the corner highest in the image
    Eigen::Vector3d best = point - u - v;
    for (const Eigen::Vector3d& c : {Eigen::Vector3d(point + u - v), Eigen::Vector3d(point + u + v), Eigen::Vector3d(point - u + v)})
      if (c.y() < best.y()) best = c;
    out.anchor = best;
  }
}

}  // namespace mereo::shapes
