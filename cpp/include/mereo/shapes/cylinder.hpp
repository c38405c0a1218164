// mereo/shapes/cylinder.hpp: a right circular cylinder (a mug's or a can's body): `point` on the
// axis at the middle of the visible extent, unit `axis`, `radius`, `height` = the visible extent
// along the axis.
#pragma once

#include <algorithm>
#include <cmath>

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Cylinder {
  static constexpr const char* name = "cylinder";
  static constexpr int sample_size = 2;  // the axis is n1 x n2 (Schnabel et al. 2007)
  static constexpr bool thin = false, solid = true, curved = true, view_centred = true;
  static constexpr std::array<const char*, 3> attributes = {"radius", "height", "aspect"};  ///< names of attribute()

  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double radius = 0.0;
  double height = 0.0;

  Eigen::Vector3d origin() const { return point; }
  std::optional<Eigen::Vector3d> direction() const { return axis; }
  double size() const { return radius; }
  double extent() const;
  double half_extent_along(const Eigen::Vector3d& dir) const;
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  static std::optional<Cylinder> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&);
  bool plausible(const Limits& l) const { return radius >= l.min_radius && radius <= l.max_radius; }
  Eigen::VectorXd pack() const;
  void unpack(const Eigen::VectorXd& v);
  bool fit_direct(const std::vector<Eigen::Vector3d>&) { return false; }
  double range_residual(const Eigen::Vector3d& x) const;
  void set_extent(const std::vector<Eigen::Vector3d>& points);
  void canonical() {}
  void transform(const Eigen::Isometry3d& T) { point = T * point, axis = T.linear() * axis; }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d) { axis = d; }
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) { point = Eigen::Vector3d(v[0], v[1], v[2]), radius = v[3], height = v[4]; }
};

/// Range residual of a camera-frame point x against the circle of `radius` about the line
/// (centre, unit_axis) (a cylinder; a sphere without an axis): x's range minus the range at which
/// its ray meets the surface, at the crossing nearer the point (the near one on an outer wall, the
/// far one on an inner wall: signed_distance's sign). A depth sensor's noise lies along the ray
/// (Nguyen, Izadi, Lovell 2012), so this is the maximum-likelihood residual. Grazing rays
/// (incidence past ~80 degrees, or a miss), where the range is ill-defined, continue with
/// `geometric()` (the signed distance) turned into range at that incidence.
template <class Geometric>
double ray_residual(const Eigen::Vector3d& x, const Eigen::Vector3d& centre, const Eigen::Vector3d* unit_axis,
                    double radius, Geometric geometric) {
  const double range = x.norm();
  if (!(range > 0)) return geometric();
  const Eigen::Vector3d d = x / range;
  Eigen::Vector3d w = d, c = centre;
  if (unit_axis) w -= *unit_axis * unit_axis->dot(d), c -= *unit_axis * unit_axis->dot(centre);
  const double ww = w.squaredNorm(), wc = w.dot(c);
  const double disc = wc * wc - ww * (c.squaredNorm() - radius * radius);  // (r cos(incidence))^2 * ww
  constexpr double kMinCos = 0.17;
  const double cos_in = disc > 0 && ww > 0 ? std::sqrt(disc / ww) / radius : 0.0;
  if (cos_in < kMinCos || ww < 1e-12) return geometric() / (kMinCos * std::sqrt(std::max(ww, 1e-12)));
  const double near = (wc - std::sqrt(disc)) / ww, far = (wc + std::sqrt(disc)) / ww;
  return std::abs(range - near) <= std::abs(range - far) ? near - range : range - far;
}

}  // namespace mereo::shapes
