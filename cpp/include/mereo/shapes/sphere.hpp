// mereo/shapes/sphere.hpp: a sphere (a bowl's outside or inside): `center`, `radius`, and `cap`:
// where on it its points were seen (the mean of the unit directions from the centre to them; 0
// when unknown). A bowl's wall is seen below its centre, a dome's above.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Sphere {
  static constexpr const char* name = "sphere";
  static constexpr int sample_size = 2;  // the centre where the normal lines meet
  static constexpr bool thin = false, solid = true, curved = true, view_centred = false;
  static constexpr std::array<const char*, 1> attributes = {"radius"};  ///< names of attribute()

  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Eigen::Vector3d cap = Eigen::Vector3d::Zero();

  Eigen::Vector3d origin() const { return center; }
  std::optional<Eigen::Vector3d> direction() const { return std::nullopt; }
  double size() const { return radius; }
  double extent() const { return radius; }
  double half_extent_along(const Eigen::Vector3d&) const { return radius; }
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  static std::optional<Sphere> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&);
  bool plausible(const Limits& l) const { return radius >= l.min_radius && radius <= l.max_radius; }
  Eigen::VectorXd pack() const;
  void unpack(const Eigen::VectorXd& v) { center = v.head<3>(), radius = v(3); }
  bool fit_direct(const std::vector<Eigen::Vector3d>&) { return false; }
  double range_residual(const Eigen::Vector3d& x) const;
  /// range_residual and its gradient over pack()'s 4 parameters
  double range_residual(const Eigen::Vector3d& x, const Eigen::VectorXd& packed, double* grad) const;
  void set_extent(const std::vector<Eigen::Vector3d>& inliers);
  void canonical() {}
  void transform(const Eigen::Isometry3d& T) { center = T * center, cap = T.linear() * cap; }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d&) {}
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) { center = Eigen::Vector3d(v[0], v[1], v[2]), radius = v[3]; }
};

}  // namespace mereo::shapes
