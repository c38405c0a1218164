// mereo/shapes/arc.hpp: an elliptical arc of the colour image (features/edges.hpp: a rim, a
// handle's outline): its ellipse (`center_px`, semi-axes `axes_px` = (major, minor), `angle_deg`
// of the major axis from the image's x axis towards y), the part of it seen (`start_deg` to
// `end_deg`, eccentric anomaly t of the point center + R(angle) (major cos t, minor sin t),
// increasing), the colours inside and outside it, and, where its pixels have depth, the 3-D
// circle they lie on (`center`, unit `normal` of its plane, `radius`, metres). Not detected in
// depth; models may name it.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Arc : Undetected<Arc> {
  static constexpr const char* name = "arc";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  /// names of attribute(): `radius` (metres; lifted arcs only), `major_px`, `span_deg`, `contrast`
  static constexpr std::array<const char*, 4> attributes = {"radius", "major_px", "span_deg", "contrast"};

  Eigen::Vector2d center_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d axes_px = Eigen::Vector2d::Zero();  ///< semi-axes, major >= minor
  double angle_deg = 0.0, start_deg = 0.0, end_deg = 0.0;
  EdgeSides sides;  ///< a: inside, b: outside
  bool lifted = false;  ///< the 3-D fields below hold (the arc's pixels had depth)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double radius = 0.0;

  /// The image point at eccentric anomaly t (degrees).
  Eigen::Vector2d at(double t_deg) const;
  double span_deg() const { return end_deg - start_deg; }
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
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d) { normal = d; }
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) { center = Eigen::Vector3d(v[0], v[1], v[2]), radius = v[3]; }
};

}  // namespace mereo::shapes
