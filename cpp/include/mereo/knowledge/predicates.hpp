// mereo/knowledge/predicates.hpp: the built-in fuzzy predicates and attributes, in [0, 1].
//
// All geometry is in one frame (camera or world, metres); `Context::up` points against gravity
// in that frame. The predicates use the segments' analytic shapes (core/segment.hpp):
//  - near(a, b; max = 0.01 m): 1 when the surfaces touch, falling to 0 at a gap of `max`; the gap
//    is the larger of the two lower bounds dist(a's surface, b's centre) - extent(b) and vice
//    versa (extent = bounding-sphere radius about the centre);
//  - intersects(a, b; tolerance = 0.003 m, inset = 0 m): for a torus and a cylinder the
//    handle-on-body function of Kasprzak et al.: the ring's inner edge (d - R_t, d = distance of
//    the torus centre to the body axis) lies inside the body radius and its outer edge outside
//    it, and the torus centre lies within the body's height, `inset` or more from either end
//    (an upright body's lower end at the support when it is seen 25 mm or more above it: its
//    foot hidden);
//    each condition a ramp of width 2*tolerance.
//    Other pairs: a's surface distance to b's centre is within b's extent;
//  - parallel / perpendicular(a, b; tolerance_deg = 10): angle between their axes (cylinder and
//    line axis, plane normal, torus/arc ring normal), 1 within tolerance, 0 beyond 2*tolerance;
//  - coaxial(a, b; tolerance_deg = 10, distance = 0.01 m): parallel and b's centre on a's axis;
//  - radial(a, b; tolerance_deg = 10): a's ring (torus, arc) lies in a plane through b's axis (its
//    normal is perpendicular to the plane of b's axis and a's centre), as a handle stands out
//    from its body; 0 when a's centre is on b's axis;
//  - protrudes(a, b; min = 0.015 m, margin = 0.005 m): a stands out of b's wall by min or more (a
//    torus and a cylinder: its outer edge d + R_t beyond the body radius; other pairs: a's centre's
//    distance to b's surface plus a's extent), 0 at min - margin;
//  - above(a, b; margin = 0.01 m): a's centre higher than b's along `up`, ramp over `margin`;
//  - on(a, b; tolerance = 0.01 m): a's lowest point at b's top (along `up`), and a's centre over
//    b (horizontal distance within b's extent);
//  - under(a, b; min = 0, max = extent(a), reach = 0.2 m, margin = 0.05 m): b stands under a (a
//    leg under a seat): b's top within `reach` below a's lowest point, and b's centre min to max
//    from a's across up (an office chair's column at the seat's middle, a dining chair's legs
//    towards its corners), each a ramp over `margin`;
//  - convex(a, b; margin = 0.02 m): each one's centre lies behind the other's surface (negative
//    signed distance), ramp over `margin`: two faces of a box at a convex edge, not a door leaf
//    standing out of its wall;
//  - same_size(a, b; ratio = 0.8): min/max of the sizes (radius, or height for lines) >= ratio
//    gives 1, falling to 0 at ratio - 0.2;
//  - distance(a, b; min = 0, max, margin = 0.01 m): centre distance within [min, max].
// and, in the image, for 2-D primitives (a line, an arc: the edge modality; 0 for other classes):
//  - parallel_px / perpendicular_px(a, b; tolerance_deg = 10): angle between their image
//    directions (a line's, an arc's major axis), 1 within tolerance, 0 beyond 2*tolerance;
//  - touches_px(a, b; max = 4 px): the nearest of either one's ends (as seen) to the other's curve
//    (an arc's whole ellipse), 1 within max, 0 beyond 2*max (a cylinder's side ends on its rim);
//  - apart_px(a, b; min = 8 px): b's middle lies off a's line (a: a line) by at least min, 0 at
//    half of it (the two sides of a cylinder's outline are two lines, not one);
//  - stacked_px(a, b; tolerance_deg = 10, ratio = 0.8, min = 8 px, max = 4): b (an arc) is a's
//    ellipse carried along a's minor axis by min pixels to max of a's major semi-axes, as a
//    cylinder's base arc lies under its rim: major axes parallel and of about one size, b's
//    centre on a's minor axis, b seen on its side away from a and beyond a's ellipse.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/segment.hpp"
#include "mereo/knowledge/model.hpp"

namespace mereo::knowledge {

struct Context {
  Eigen::Vector3d up = -Eigen::Vector3d::UnitY();  ///< against gravity (camera frame: -y)
  /// The support surface's offset: up.dot(x) + support_d is a point's height above it; NaN when
  /// there is none (then nothing is judged by its rest on it).
  double support_d = std::numeric_limits<double>::quiet_NaN();
};

const std::vector<std::string>& builtin_predicates();
bool is_builtin_predicate(const std::string& name);
/// The parameters a built-in predicate accepts (for checking model files).
const std::vector<std::string>& predicate_params(const std::string& name);

/// Attribute names: those of the shape table's classes (a cylinder's radius, height and aspect =
/// height / diameter, a torus's minor_radius, a plane's d...: mereo/shapes/*.hpp; NaN for a class
/// that lacks one), then tilt_deg (angle between the axis and `up`), rest_tilt_deg (the angle to
/// the nearer of the two rest poses of a body on a table, upright and lying: min(tilt, 90 - tilt)),
/// elevation (centre height
/// along up, metres), rest_gap (an axial body's lowest point above the support surface, metres:
/// negative where it would pass through it; +infinity without a support, NaN for a body without
/// radius and height), inliers, residual, hue
/// (degrees), inward (1 for a surface seen from inside: a mug's inner wall), top and bottom (its
/// highest and lowest point above the support, metres), span_up (its extent along up: a door
/// leaf's height seen, not the longer side of a wide strip of wall).
const std::vector<std::string>& attribute_names();
bool is_attribute(const std::string& name);
double attribute_value(const Segment& s, const std::string& name, const Context& context);
/// The membership of a part's attribute in its range. A patch whose upper (lower) edge is hidden
/// (shapes::Patch::top_hidden, bottom_hidden: it runs out of the image or behind something
/// nearer) reaches at least as high (low) as seen: its `top` (`bottom`) scores as the best value
/// at or above (below) the one seen, a door cut by the image's top edge as a whole one.
double attribute_membership(const Segment& s, const Attribute& a, const Context& context);

/// The value of a constraint on the parts' data (custom or built-in), clamped to [0, 1].
double evaluate(const Constraint& c, const std::vector<const Segment*>& parts,
                const Context& context);

/// A constraint prepared for repeated evaluation (the predicate looked up and its parameters
/// read once): compile(c)(parts, context) == evaluate(c, parts, context), exactly.
using CompiledConstraint = std::function<double(const std::vector<const Segment*>& parts, const Context& context)>;
CompiledConstraint compile(const Constraint& c);

/// Distance from p to the surface of s (its solid for closed shapes); >= 0 outside.
double surface_distance(const Segment& s, const Eigen::Vector3d& p);
/// Radius of a bounding sphere of s about s.point (0 for unbounded planes).
double extent(const Segment& s);

}  // namespace mereo::knowledge
