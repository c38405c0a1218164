// mereo/shapes/line.hpp: a straight edge of the colour image (features/edges.hpp): its end pixels
// `start_px`, `end_px` (image coordinates, x right, y down, pixel centres at integers), the
// colours on its two sides, and, where its pixels have depth, the 3-D segment they lie on
// (`point` at its middle, unit `axis`, `length`, metres). Not detected in depth; models may name it.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Line : Undetected<Line> {
  static constexpr const char* name = "line";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  /// names of attribute(): `length` (metres; lifted lines only), `length_px`, `contrast`
  static constexpr std::array<const char*, 4> attributes = {"length", "height", "length_px", "contrast"};

  Eigen::Vector2d start_px = Eigen::Vector2d::Zero(), end_px = Eigen::Vector2d::Zero();
  EdgeSides sides;  ///< a: left, b: right, walking from start_px to end_px
  bool lifted = false;  ///< the 3-D fields below hold (the line's pixels had depth)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double length = 0.0;

  double length_px() const { return (end_px - start_px).norm(); }
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
