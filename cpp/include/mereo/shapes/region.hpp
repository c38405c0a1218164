// mereo/shapes/region.hpp: a free-form region standing on the support (a squeeze bottle, a
// drill, a box: a connected surface above the table that is no primitive), as the upright box
// that holds its points: `point` at the box's centre, unit `axis` up (the support's normal), unit
// `width_axis` along its width, `width` and `thickness` (the visible extents across the axis),
// `height` (from the support to its top), `foot` (the height of its lowest points: 0 for what
// stands on the support in view, more where its foot is hidden or it rests on something else) and
// `neck` (the width of its top sixth over its width: about 1 for a box, under 0.6 for a bottle's
// cap). Not detected by RANSAC: found by
// features::free_form_regions; models may name it.
#pragma once

#include <cmath>

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Region : Undetected<Region> {
  static constexpr const char* name = "region";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  static constexpr std::array<const char*, 6> attributes = {"width", "thickness", "height", "foot", "neck",
                                                            "slenderness"};  ///< names of attribute()

  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d width_axis = Eigen::Vector3d::UnitX();
  double width = 0.0, thickness = 0.0, height = 0.0, foot = 0.0, neck = 1.0;

  Eigen::Vector3d origin() const { return point; }
  std::optional<Eigen::Vector3d> direction() const { return axis; }
  double size() const { return width / 2; }
  double extent() const { return 0.5 * std::sqrt(width * width + thickness * thickness + height * height); }
  double half_extent_along(const Eigen::Vector3d& dir) const;
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const;
  double surface_distance(const Eigen::Vector3d& x) const;
  void transform(const Eigen::Isometry3d& T) {
    point = T * point, axis = T.linear() * axis, width_axis = T.linear() * width_axis;
  }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d);
  void tracked(TrackedParams& t) const;
  void set_tracked(const double* v) {
    point = Eigen::Vector3d(v[0], v[1], v[2]), width = v[3], thickness = v[4], height = v[5];
  }

 private:
  /// The box's unit axes: width_axis, depth (axis x width_axis), axis; and its half sizes along them.
  void frame(Eigen::Vector3d e[3], double half[3]) const;
};

}  // namespace mereo::shapes
