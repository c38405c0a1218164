// mereo/shapes/patch.hpp: a bounded planar patch (a table top, a chair's seat or back, a door, a
// wall) as the rectangle that holds its points in their plane: `point` at the rectangle's centre,
// unit `normal` towards the camera, unit `u_axis` in the plane (horizontal for a patch that
// stands upright when gravity is known, else its points' main direction), `size_u` along u_axis
// and `size_v` across it (metres; the 2nd to 98th percentiles of the points), `area` (square
// metres: its pixels' footprint on the plane, what is seen of it, not the rectangle's),
// `open_below` (with gravity known: the share of what is seen 0.12-0.3 m below its lower edge in
// the image that lies far behind that edge, not at its depth: 1 for a table top or a seat on
// legs, or a chair's back seen from behind, 0 for a box's or a cabinet's top with its front
// below; NaN unmeasured), `top_hidden` and `bottom_hidden` (an upright patch whose upper or lower
// edge runs out of the image or behind something nearer along most of its length: it may reach
// higher or lower than seen; knowledge::attribute_membership scores its `top`, `bottom` so),
// `far_hidden` (a level patch whose far edge, its upper one in the image, runs behind something
// along most of its length: a nearer surface, or one that rises from the patch's plane, as a
// cushion or a printer on a table top: the top may reach further than seen),
// `side_cut` (the share of its rows that run out of the image at its left or right side: its
// width there is not its own), `stands_out` (an upright patch's: the share of its rows' left and
// right ends, inside the image, beyond which the depth lies far behind: 1 for a cabinet's front
// before its wall, 0 for a piece of wall or a closed door in it; NaN unmeasured), `flush` (an
// upright patch whose centre lies within 1 cm of the plane of a larger upright patch parallel to
// it: a piece of that wall parted from the rest by what stands before it; a closed door's leaf
// lies a leaf's or a frame's depth off its wall). Attributes:
// `length`, `width` (the rectangle's longer and shorter side), `area`, `open_below`, `side_cut`,
// `stands_out`, `top_hidden`, `bottom_hidden`, `far_hidden` and `flush` (0 or 1), `view_deg` (the angle between its
// normal and the line of sight to its centre, in the frame it was found in: 0 seen square on). Not
// detected by RANSAC: found by features::planar_patches; models name it (graphs/models/room.yaml).
#pragma once

#include <algorithm>
#include <cmath>

#include "mereo/shapes/shape.hpp"

namespace mereo::shapes {

struct Patch : Undetected<Patch> {
  static constexpr const char* name = "patch";
  static constexpr bool thin = false, solid = false, curved = false, view_centred = false;
  static constexpr std::array<const char*, 11> attributes = {"length",       "width",         "area",
                                                            "open_below",   "side_cut",      "stands_out",
                                                            "top_hidden",   "bottom_hidden", "far_hidden",
                                                            "flush",        "view_deg"};  ///< names of attribute()

  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();
  double size_u = 0.0, size_v = 0.0, area = 0.0;
  double open_below = std::nan("");
  bool top_hidden = false, bottom_hidden = false;  ///< an upright patch's upper, lower edge hidden
  bool far_hidden = false;                          ///< a level patch's far edge hidden
  bool flush = false;                               ///< upright, in the plane of a larger upright patch
  double side_cut = 0.0;                            ///< the share of its rows cut by the image's sides
  double stands_out = std::nan("");                 ///< the share of its sides before far depth

  /// The in-plane axis across u_axis.
  Eigen::Vector3d v_axis() const { return normal.normalized().cross(u_axis).normalized(); }
  Eigen::Vector3d origin() const { return point; }
  std::optional<Eigen::Vector3d> direction() const { return normal; }
  double size() const { return 0.5 * std::max(size_u, size_v); }
  double extent() const { return 0.5 * std::hypot(size_u, size_v); }
  double half_extent_along(const Eigen::Vector3d& dir) const {
    return 0.5 * (std::abs(u_axis.dot(dir)) * size_u + std::abs(v_axis().dot(dir)) * size_v);
  }
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n = nullptr) const {
    if (n) *n = normal;
    return normal.dot(x - point);
  }
  double surface_distance(const Eigen::Vector3d& x) const;  ///< to the rectangle
  void transform(const Eigen::Isometry3d& T) {
    point = T * point, normal = T.linear() * normal, u_axis = T.linear() * u_axis;
  }
  void canonical() {
    if (normal.dot(point) > 0) normal = -normal;  // towards the camera
  }
  void fields(FieldList& out, bool inward) const;
  bool set_field(const std::string& key, const FieldValue& v);
  std::optional<double> attribute(const std::string& key) const;
  void outline(Outline& out) const;
  void set_direction(const Eigen::Vector3d& d) {
    normal = d.normalized();
    u_axis = unit_across(u_axis, normal);
  }
  void tracked(TrackedParams& t) const {
    for (int i = 0; i < 3; ++i) t.add(point(i), false);
    t.add(size_u, false), t.add(size_v, false);
  }
  void set_tracked(const double* v) { point = Eigen::Vector3d(v[0], v[1], v[2]), size_u = v[3], size_v = v[4]; }
};

}  // namespace mereo::shapes
