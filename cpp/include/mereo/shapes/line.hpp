// mereo/shapes/line.hpp: a straight segment (an edge, a leg's axis): `point` at its middle, unit
// `axis`, `length`. Not detected in depth; models may name it.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Line : Undetected<Line> {
  static constexpr const char* name = "line";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  static constexpr std::array<const char*, 2> attributes = {"length", "height"};  ///< names of attribute()

  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double length = 0.0;

  Eigen::Vector3d origin() const { return point; }
  std::optional<Eigen::Vector3d> direction() const { return axis; }
  double size() const { return length; }
  double extent() const { return length / 2; }
  double half_extent_along(const Eigen::Vector3d& dir) const;
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  void transform(const Eigen::Isometry3d& T) { point = T * point, axis = T.linear() * axis; }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d) { axis = d; }
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) { point = Eigen::Vector3d(v[0], v[1], v[2]), length = v[3]; }
};

}  // namespace mereo::shapes
