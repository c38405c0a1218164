// mereo/shapes/torus.hpp: a torus (a mug's handle, seen as the part of a ring outside the body):
// `center`, unit `normal` = the ring's axis of symmetry, `major_radius` of the ring,
// `minor_radius` of the tube.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Torus {
  static constexpr const char* name = "torus";
  static constexpr int sample_size = 4;  // see from_sample
  static constexpr bool thin = true, solid = true, curved = false, view_centred = false;
  static constexpr std::array<const char*, 3> attributes = {"radius", "major_radius", "minor_radius"};  ///< names of attribute()

  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double major_radius = 0.0;
  double minor_radius = 0.0;

  Eigen::Vector3d origin() const { return center; }
  std::optional<Eigen::Vector3d> direction() const { return normal; }
  double size() const { return major_radius; }
  double extent() const { return major_radius + minor_radius; }
  double half_extent_along(const Eigen::Vector3d& dir) const;
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  /// Four points (Schnabel et al. 2007): the tube radius r moves them by -r along their normals
  /// onto the ring's plane (a cubic in r, its root within the limits' tube range); the ring is the
  /// circle through three of them, and the fourth must lie on it too.
  static std::optional<Torus> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits& l);
  bool plausible(const Limits& l) const {
    return minor_radius >= l.min_minor_radius && minor_radius <= l.max_minor_radius && major_radius > minor_radius &&
           major_radius <= l.max_major_radius;
  }
  Eigen::VectorXd pack() const;
  void unpack(const Eigen::VectorXd& v);
  bool fit_direct(const std::vector<Eigen::Vector3d>&) { return false; }
  double range_residual(const Eigen::Vector3d& x) const { return signed_distance(x); }
  void set_extent(const std::vector<Eigen::Vector3d>&) {}
  void canonical() {}
  void transform(const Eigen::Isometry3d& T) { center = T * center, normal = T.linear() * normal; }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d) { normal = d; }
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) {
    center = Eigen::Vector3d(v[0], v[1], v[2]), major_radius = v[3], minor_radius = v[4];
  }
};

}  // namespace mereo::shapes
