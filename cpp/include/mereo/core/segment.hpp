// mereo/core/segment.hpp: a detected primitive (the feature layer's output, the object layer's
// data instance). Coordinates in metres, camera frame, unless a field says world.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/shapes/table.hpp"

namespace mereo {

/// One segment: its class's parameter block (`shape`: one of the shape table's classes, see
/// mereo/shapes/), its inlier pixels and attributes. The generic functions below forward to the
/// class; code that needs one class's parameters asks for it: `s.as<shapes::Cylinder>().radius`.
struct Segment {
  int id = -1;
  Geometry shape;                   ///< the class and its parameters
  std::size_t inliers = 0;          ///< number of inlier pixels
  double residual = 0.0;            ///< RMS point-to-surface distance of the inliers, metres
  Eigen::Vector3f mean_color = Eigen::Vector3f::Zero();  ///< RGB in [0, 1]
  double hue = 0.0;                 ///< degrees [0, 360) of mean_color
  /// Solid shapes: seen from inside (its pixels' normals point towards the axis or centre: a
  /// mug's inner wall, a bowl's inside), not from outside.
  bool inward = false;
  /// Axial solids (cylinders, cones) seen from outside: of the valid pixels whose rays cross the
  /// end cap facing the camera, those that stop on the cap (a lid) and those that pass it into
  /// the body (an open vessel seen into); 0 and 0 when no end faces the camera.
  int end_closed = 0, end_open = 0;
  /// Axial solids: how much the surface bends along the axis as the normals show it (1 / m; 0 when
  /// the normals show no consistent bend): a banana fitted by a cylinder does, a can does not.
  double bend = 0.0;
  /// Axial solids seen from outside: how far the cross-section is from a circle, as the RMS of
  /// the pattern its pixels' distances from the surface make around the axis, over the radius (0
  /// when they show none beyond noise): a rounded box fitted by a cylinder is, a can is not.
  double out_of_round = 0.0;
  std::vector<int> pixels;          ///< inlier pixel indices v * width + u

  Segment() = default;
  explicit Segment(Geometry g) : shape(std::move(g)) {}

  PrimitiveClass cls() const { return PrimitiveClass::at(shape.index()); }
  const char* class_name() const { return cls().name(); }
  template <class S>
  bool is() const { return std::holds_alternative<S>(shape); }
  template <class S>
  const S& as() const { return std::get<S>(shape); }
  template <class S>
  S& as() { return std::get<S>(shape); }
  template <class S>
  const S* get_if() const { return std::get_if<S>(&shape); }
  template <class F>
  decltype(auto) visit(F&& f) const { return std::visit(std::forward<F>(f), shape); }
  template <class F>
  decltype(auto) visit(F&& f) { return std::visit(std::forward<F>(f), shape); }

  // ---- the table's functions (see mereo/shapes/shape.hpp) ----
  Eigen::Vector3d origin() const { return visit([](const auto& s) { return s.origin(); }); }
  std::optional<Eigen::Vector3d> direction() const { return visit([](const auto& s) { return s.direction(); }); }
  double size() const { return visit([](const auto& s) { return s.size(); }); }
  double extent() const { return visit([](const auto& s) { return s.extent(); }); }
  double half_extent_along(const Eigen::Vector3d& dir) const {
    return visit([&](const auto& s) { return s.half_extent_along(dir); });
  }
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* normal = nullptr) const {
    return visit([&](const auto& s) { return s.signed_distance(x, normal); });
  }
  double surface_distance(const Eigen::Vector3d& x) const {
    return visit([&](const auto& s) { return s.surface_distance(x); });
  }
  bool solid() const { return visit([](const auto& s) { return std::decay_t<decltype(s)>::solid; }); }
  bool curved() const { return visit([](const auto& s) { return std::decay_t<decltype(s)>::curved; }); }
  bool view_centred() const {
    return visit([](const auto& s) { return std::decay_t<decltype(s)>::view_centred; });
  }
  /// A class-specific model attribute ("radius", "height", "minor_radius", "aspect", "d"...);
  /// nullopt when the class has none of that name.
  std::optional<double> attribute(const std::string& name) const {
    return visit([&](const auto& s) { return s.attribute(name); });
  }
  /// The same segment moved by a rigid transform (camera to world and back).
  Segment transformed(const Eigen::Isometry3d& T) const {
    Segment out = *this;
    out.visit([&](auto& s) { s.transform(T); });
    return out;
  }
  /// The class's JSON fields, in the contract's order (mereo/shapes/*.hpp).
  shapes::FieldList fields() const {
    shapes::FieldList out;
    visit([&](const auto& s) { s.fields(out, inward); });
    return out;
  }
  /// Sets a field by its JSON name (or an alias, e.g. a torus's "radius" for "major_radius");
  /// false when the class has no such field or the value is of another kind.
  bool set_field(const std::string& name, const shapes::FieldValue& v) {
    return visit([&](auto& s) { return s.set_field(name, v); });
  }
  shapes::Outline outline() const {
    shapes::Outline out;
    visit([&](const auto& s) { s.outline(out); });
    return out;
  }
};

}  // namespace mereo
