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
  // (inline: the search's loops over pixels call it millions of times per frame)
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const {
    const Eigen::Vector3d q = x - point;
    const Eigen::Vector3d radial = q - axis * axis.dot(q);
    const double l = radial.norm();
    if (n) *n = l > 0 ? Eigen::Vector3d(radial / l) : Eigen::Vector3d::UnitX();
    return l - radius;
  }
  double surface_distance(const Eigen::Vector3d& x) const;
  static std::optional<Cylinder> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&);
  bool plausible(const Limits& l) const { return radius >= l.min_radius && radius <= l.max_radius; }
  Eigen::VectorXd pack() const;
  void unpack(const Eigen::VectorXd& v);
  bool fit_direct(const std::vector<Eigen::Vector3d>&) { return false; }
  double range_residual(const Eigen::Vector3d& x) const;
  /// range_residual and its gradient over pack()'s 7 parameters at `packed` (this cylinder unpacked)
  double range_residual(const Eigen::Vector3d& x, const Eigen::VectorXd& packed, double* grad) const;
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
/// the geometric (signed) distance turned into range at that incidence.
/// With `grad`, also d residual / d (centre (3), axis (3, when there is one; `axis_scale` is the
/// length of the unnormalised axis the unit one came from), radius): the crossing's range t solves
/// F(t) = |t w - c|^2 - r^2 = 0, so dt = -dF / (dF/dt) with g = t w - c the radial vector there:
/// dt/dcentre = g / (g . w), dt/daxis = (axis . (t d - centre)) g / (g . w) (within the plane
/// orthogonal to the axis, over axis_scale), dt/dr = r / (g . w).
inline double ray_residual(const Eigen::Vector3d& x, const Eigen::Vector3d& centre, const Eigen::Vector3d* unit_axis,
                           double radius, double axis_scale = 1.0, double* grad = nullptr) {
  const int R = unit_axis ? 6 : 3;  // (the radius' index)
  // the geometric distance (signed_distance) and its gradient, divided by `scale`
  const auto geometric = [&](double scale) {
    const Eigen::Vector3d q = x - centre;
    const Eigen::Vector3d h = unit_axis ? Eigen::Vector3d(q - *unit_axis * unit_axis->dot(q)) : q;
    const double l = h.norm(), value = l - radius;
    if (grad) {
      const Eigen::Vector3d hn = l > 0 ? Eigen::Vector3d(h / l) : Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) grad[k] = -hn(k) / scale;
      if (unit_axis)
        for (int k = 0; k < 3; ++k) grad[3 + k] = -unit_axis->dot(q) * hn(k) / axis_scale / scale;
      grad[R] = -1.0 / scale;
    }
    return value / scale;
  };
  const double range = x.norm();
  if (!(range > 0)) return geometric(1.0);
  const Eigen::Vector3d d = x / range;
  Eigen::Vector3d w = d, c = centre;
  if (unit_axis) w -= *unit_axis * unit_axis->dot(d), c -= *unit_axis * unit_axis->dot(centre);
  const double ww = w.squaredNorm(), wc = w.dot(c);
  const double disc = wc * wc - ww * (c.squaredNorm() - radius * radius);
  constexpr double kMinCos = 0.17;
  const double cos_in = disc > 0 && ww > 0 ? std::sqrt(disc / ww) / radius : 0.0;
  if (cos_in < kMinCos || ww < 1e-12) {
    const double s = std::sqrt(std::max(ww, 1e-12));
    const double value = geometric(kMinCos * s);
    // the incidence factor 1 / s turns with the axis: d s / d axis = -(axis . d) w / s
    if (grad && unit_axis && ww >= 1e-12)
      for (int k = 0; k < 3; ++k) grad[3 + k] += value / s * unit_axis->dot(d) * w(k) / s / axis_scale;
    return value;
  }
  const double near = (wc - std::sqrt(disc)) / ww, far = (wc + std::sqrt(disc)) / ww;
  const bool near_side = std::abs(range - near) <= std::abs(range - far);
  if (grad) {
    const double t = near_side ? near : far, sign = near_side ? 1.0 : -1.0;
    const Eigen::Vector3d g = t * w - c;
    const double gw = g.dot(w);
    for (int k = 0; k < 3; ++k) grad[k] = sign * g(k) / gw;
    if (unit_axis) {
      const double along = unit_axis->dot(t * d - centre);
      for (int k = 0; k < 3; ++k) grad[3 + k] = sign * along * g(k) / gw / axis_scale;
    }
    grad[R] = sign * radius / gw;
  }
  return near_side ? near - range : range - far;
}

}  // namespace mereo::shapes
