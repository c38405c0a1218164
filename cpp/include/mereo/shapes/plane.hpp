// mereo/shapes/plane.hpp: an unbounded plane (a table top, a wall): unit `normal` towards the
// camera, `d` with normal.dot(x) + d = 0, `point` = centroid of its inliers.
#pragma once

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Plane {
  static constexpr const char* name = "plane";
  static constexpr int sample_size = 1;
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  static constexpr std::array<const char*, 1> attributes = {"d"};  ///< names of attribute()

  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();

  Eigen::Vector3d origin() const { return point; }
  std::optional<Eigen::Vector3d> direction() const { return normal; }
  double size() const { return 0.0; }
  double extent() const { return 0.0; }
  double half_extent_along(const Eigen::Vector3d&) const { return 0.0; }
  // (inline: the search's loops over pixels call it millions of times per frame)
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const {
    if (n) *n = normal;
    return normal.dot(x) + d;
  }
  double surface_distance(const Eigen::Vector3d& x) const;
  static std::optional<Plane> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&);
  bool plausible(const Limits&) const { return true; }
  Eigen::VectorXd pack() const { return {}; }
  void unpack(const Eigen::VectorXd&) {}
  bool fit_direct(const std::vector<Eigen::Vector3d>& points);
  double range_residual(const Eigen::Vector3d& x) const { return signed_distance(x); }
  void set_extent(const std::vector<Eigen::Vector3d>& points);
  void canonical();
  void transform(const Eigen::Isometry3d& T);
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline&) const {}
  void set_direction(const Eigen::Vector3d& d) { normal = d; }
  void tracked(TrackedParams& t) const {
    for (int i = 0; i < 3; ++i) t.add(point(i), false);
  }
  void set_tracked(const double* v) { point = Eigen::Vector3d(v[0], v[1], v[2]); }
};

}  // namespace mereo::shapes
