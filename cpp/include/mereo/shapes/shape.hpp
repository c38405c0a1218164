// mereo/shapes/shape.hpp: what every entry of the shape table provides, and the small types
// they share. Metres, camera frame (or world: a shape does not care) unless a field says.
//
// A primitive class is one struct in one file pair (mereo/shapes/<name>.hpp, cpp/src/shapes/
// <name>.cpp) holding its parameter block and giving everything the rest of the library needs
// to know about the class; the list of classes is mereo/shapes/table.hpp. Each struct S has:
//
//   static constexpr const char* name;        "cylinder" (the JSON output's "class")
//   static constexpr int sample_size;         points with normals of a RANSAC minimal set; 0 = not
//                                             detected bottom-up
//   static constexpr bool thin;               a thin part (a handle's tube): small sampling window,
//                                             the small-part support, fewer local hits
//   static constexpr bool solid;              has an inside and an outside (segments seen from
//                                             inside are `inward`); a plane has not
//   static constexpr bool curved;             measured on the unfiltered depth along the rays
//   static constexpr bool view_centred;       origin() is the middle of the visible extent along the
//                                             axis: it moves with the view (a cylinder's centre)
//   the parameter block (public fields)
//   Eigen::Vector3d origin() const;           the placement point (JSON point or center)
//   std::optional<Eigen::Vector3d> direction() const;   axis or normal; none for a sphere
//   double size() const;                      for same_size: a radius, a line's length
//   double extent() const;                    bounding-sphere radius about origin()
//   double half_extent_along(const Eigen::Vector3d& unit_dir) const;
//   double signed_distance(x, Eigen::Vector3d* normal) const;   to the unbounded surface (RANSAC)
//   double surface_distance(x) const;         to the bounded surface or solid, >= 0 (predicates)
//   static std::optional<S> from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits&);
//   bool plausible(const Limits&) const;      within the detector's ranges
//   Eigen::VectorXd pack() const; void unpack(const Eigen::VectorXd&);   least-squares parameters
//                                             (empty: no iterative refit)
//   bool fit_direct(const std::vector<Eigen::Vector3d>&);   a closed-form refit (plane: PCA); false
//                                             when the class has none
//   double range_residual(const Eigen::Vector3d& x) const;  range error along x's ray
//   double range_residual(x, packed, double* grad) const;   optional: the same and its gradient over
//                                             pack()'s parameters (the refit's Jacobian in closed form)
//   void set_extent(const std::vector<Eigen::Vector3d>& inliers);   visible extent, centroid
//   void canonical();                         a sign convention (a plane's normal faces the camera)
//   void transform(const Eigen::Isometry3d& T);
//   void fields(FieldList&, bool inward) const;   the JSON fields, in the contract's order
//   bool set_field(const std::string&, const FieldValue&);   from JSON or Python (aliases too)
//   std::optional<double> attribute(const std::string&) const;  class-specific model attributes
//   static constexpr std::array<const char*, N> attributes;      ... and their names
//   void outline(Outline&) const;             3-D polylines for drawing (camera frame)
//   void tracked(TrackedParams&) const; void set_tracked(const double*);   what a tracker filters
//   void set_direction(const Eigen::Vector3d&);   the axis or normal (a tracker's running mean)
// and optionally, for a class that generalizes another (a cone: a cylinder of no taper):
//   using Refines = Special; static S refined_from(const Special&);   the detector then tries a
//                                             segment of the special class as this one
//   double departure() const; static constexpr double min_departure;   ... kept only this far
//                                             from the special class (a cone's taper); closer, it
//   Special simplified() const;               is taken for the special class when that is wanted
#pragma once

#include <array>
#include <optional>
#include <type_traits>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mereo::shapes {

/// The detector's plausible ranges (features::DetectOptions's radii).
struct Limits {
  double min_radius = 0.01;        ///< cylinder and sphere radius, a cone's larger radius
  double max_radius = 0.35;
  double min_minor_radius = 0.003; ///< torus tube radius
  double max_minor_radius = 0.02;
  double max_major_radius = 0.08;  ///< torus ring radius
};

/// A field of the JSON output and of Python's Segment: a number, a flag, a 3-vector (metres, a
/// direction, a colour) or a 2-vector (pixels: a 2-D primitive's image coordinates).
using FieldValue = std::variant<double, bool, Eigen::Vector3d, Eigen::Vector2d>;
using FieldList = std::vector<std::pair<const char*, FieldValue>>;

/// Polylines to draw (camera frame; `pixels`: in image coordinates, a 2-D primitive's) and where
/// a label may go.
struct Outline {
  std::vector<std::vector<Eigen::Vector3d>> lines;
  std::vector<std::vector<Eigen::Vector2d>> pixels;
  std::optional<Eigen::Vector3d> anchor;
};

/// The parameters a tracker filters across views: the centre first (3 values, position
/// noise), then `value`s flagged `size` (slow: radii) or not (extents that follow the view).
struct TrackedParams {
  std::vector<double> value;
  std::vector<bool> size;
  void add(double v, bool is_size) { value.push_back(v), size.push_back(is_size); }
};

/// A circle of `radius` about `centre` in the plane normal to `axis`, `samples` points.
std::vector<Eigen::Vector3d> circle(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius,
                                    int samples = 64);

/// The outline of a frustum about `axis` (a cylinder: equal radii): its end circles at
/// point -/+ height/2 (radii r0, r1), its two silhouette lines as seen from the origin (the
/// camera), and a label anchor above its upper end.
void frustum_outline(const Eigen::Vector3d& point, const Eigen::Vector3d& axis, double height, double r0, double r1,
                     Outline& out);

/// Angle-free helpers shared by the shapes.
inline Eigen::Vector3d across(const Eigen::Vector3d& q, const Eigen::Vector3d& unit_axis) {
  return q - unit_axis * unit_axis.dot(q);
}
/// The unit direction of `q` across `unit_axis` (any one across it when q is along it).
inline Eigen::Vector3d unit_across(const Eigen::Vector3d& q, const Eigen::Vector3d& unit_axis) {
  const Eigen::Vector3d a = across(q, unit_axis);
  return a.norm() > 1e-9 ? Eigen::Vector3d(a.normalized()) : unit_axis.unitOrthogonal();
}

/// What a class that is not detected in depth (a line, an arc: models may name them) gives for
/// the detector's part of the interface: no minimal set, no refit, no extent, no sign convention.
template <class S>
struct Undetected {
  static constexpr int sample_size = 0;
  static std::optional<S> from_sample(const Eigen::Vector3d*, const Eigen::Vector3d*, const Limits&) {
    return std::nullopt;
  }
  bool plausible(const Limits&) const { return false; }
  Eigen::VectorXd pack() const { return {}; }
  void unpack(const Eigen::VectorXd&) {}
  bool fit_direct(const std::vector<Eigen::Vector3d>&) { return false; }
  double range_residual(const Eigen::Vector3d& x) const { return static_cast<const S*>(this)->signed_distance(x); }
  void set_extent(const std::vector<Eigen::Vector3d>&) {}
  void canonical() {}
};

/// What a 2-D primitive (an edge's line or arc, features/edges.hpp) shows across it: the mean
/// colours of its two sides (RGB in [0, 1], sampled a few pixels off the edge; a line's left and
/// right walking from its start to its end in the image, an arc's inside and outside).
struct EdgeSides {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  /// The colour difference across the edge, 0 .. sqrt(3).
  double contrast() const { return (a - b).norm(); }
};

/// Whether shape S generalizes another (S::Refines, S::refined_from; see above).
template <class S, class = void>
struct has_refines : std::false_type {};
template <class S>
struct has_refines<S, std::void_t<typename S::Refines>> : std::true_type {};

/// The value of a field as a number / vector; nullopt for the other kinds.
std::optional<double> number(const FieldValue& v);
std::optional<Eigen::Vector3d> vector3(const FieldValue& v);
std::optional<Eigen::Vector2d> vector2(const FieldValue& v);

}  // namespace mereo::shapes
