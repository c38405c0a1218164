// mereo/shapes/arc.hpp: a circular arc (a rim, a handle's centre line): `center`, unit `normal`
// of its plane, `radius`. Not detected in depth; models may name it.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Arc : Undetected<Arc> {
  static constexpr const char* name = "arc";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  static constexpr std::array<const char*, 1> attributes = {"radius"};  ///< names of attribute()

  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double radius = 0.0;

  Eigen::Vector3d origin() const { return center; }
  std::optional<Eigen::Vector3d> direction() const { return normal; }
  double size() const { return radius; }
  double extent() const { return radius; }
  double half_extent_along(const Eigen::Vector3d& dir) const;
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  void transform(const Eigen::Isometry3d& T) { center = T * center, normal = T.linear() * normal; }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const { out.lines.push_back(circle(center, normal, radius)); }
  void set_direction(const Eigen::Vector3d& d) { normal = d; }
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) { center = Eigen::Vector3d(v[0], v[1], v[2]), radius = v[3]; }
};

}  // namespace mereo::shapes
