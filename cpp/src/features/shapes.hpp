// Internal: the four shapes' distances and normals, minimal-set solvers and least-squares refits
// of the feature layer (features/primitives.hpp). Metres, camera frame.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/segment.hpp"

namespace mereo::features::detail {

/// Signed distance of x to the (unbounded) surface of s and the surface's unit normal at the
/// closest point (any orientation).
double signed_distance(const Segment& s, const Eigen::Vector3d& x, Eigen::Vector3d* normal = nullptr);

/// Minimal sets (Schnabel et al. 2007): a plane from one point and normal; a sphere from two;
/// a cylinder from two (axis n1 x n2); a torus from four (tube radius r: the four points moved by
/// -r along their normals are coplanar, a cubic in r; the ring is the circle through three of
/// them). nullopt when degenerate.
std::optional<Segment> plane_from(const Eigen::Vector3d& p, const Eigen::Vector3d& n);
std::optional<Segment> sphere_from(const Eigen::Vector3d& p1, const Eigen::Vector3d& n1, const Eigen::Vector3d& p2,
                                   const Eigen::Vector3d& n2);
std::optional<Segment> cylinder_from(const Eigen::Vector3d& p1, const Eigen::Vector3d& n1, const Eigen::Vector3d& p2,
                                     const Eigen::Vector3d& n2);
std::optional<Segment> torus_from(const Eigen::Vector3d* p, const Eigen::Vector3d* n, double min_minor,
                                  double max_minor);

/// At most `max_points` of `points`, evenly strided (deterministic): `points` itself when it has
/// no more, else `buffer`, filled with them.
const std::vector<Eigen::Vector3d>& subsample_into(const std::vector<Eigen::Vector3d>& points,
                                                   std::vector<Eigen::Vector3d>& buffer, std::size_t max_points);

/// What a least-squares refit minimises.
///  - Geometric: the distance of each point to the surface.
///  - AlongRay: cylinders and spheres, camera-frame points: the difference between each point's
///    range and the range at which its pixel's ray meets the surface. A depth sensor's noise
///    lies along the ray (Nguyen, Izadi, Lovell 2012), so this is the maximum-likelihood fit;
///    the geometric one is biased on a curved surface (a cylinder's radius by up to -1 mm at
///    1.5 m). Grazing rays fall back on the geometric distance. Other classes: geometric.
enum class Residual { Geometric, AlongRay };

/// Range residual of camera-frame point x against cylinder or sphere s (Residual::AlongRay), with
/// signed_distance's sign; other classes: signed_distance.
double range_residual(const Segment& s, const Eigen::Vector3d& x);

/// Levenberg-Marquardt on `residual`, from `s` (planes: PCA). Sets residual (RMS of the geometric
/// distance).
Segment refit_points(const Segment& s, const std::vector<Eigen::Vector3d>& points,
                     Residual residual = Residual::Geometric);

/// A handle's torus attached to `body` refined by Levenberg-Marquardt on the geometric distance,
/// from `t0`, with its ring plane held through the body's axis (5 parameters: azimuth, height,
/// distance of the centre from the axis, ring radius, tube radius). Only the side of a thin tube
/// that faces the camera is seen; a free fit can then trade a tilted ring plane for a fat tube,
/// while with the plane held the tube radius is how far the points stand out of it.
/// With `fix_minor`, the tube radius stays t0's (4 parameters): on a far, noisy handle only the
/// ring is well determined.
Segment refit_handle(const Segment& body, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                     bool fix_minor = false);

/// refit_handle with the tube free when that fit passes `plausible`, else with the tube held (a
/// fat tube can swallow a turned ring).
template <class Plausible>
Segment refit_handle_or_hold(const Segment& body, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                             Plausible plausible) {
  Segment free_fit = refit_handle(body, t0, points);
  return plausible(free_fit) ? free_fit : refit_handle(body, t0, points, true);
}

/// How a handle's ring plane would rather turn about the body's axis (0: it holds the axis, as a
/// handle's does; a ring leaning on a jar is turned): the fit of refit_handle (tube held) with the
/// turn free as well, against the fit with the plane held.
struct HandleTurn {
  double turn_deg = 0.0;    ///< the best turn, -90..90
  double rms_held = 0.0;    ///< the residual (metres) with the plane through the axis
  double rms_turned = 0.0;  ///< with the plane turned
};
HandleTurn handle_turn(const Segment& body, const Segment& t, const std::vector<Eigen::Vector3d>& points);

/// Cylinder: `point` moved to the middle of the points' extent along the axis and `height` set;
/// plane: `point` = centroid. Others unchanged.
void set_extent(Segment& s, const std::vector<Eigen::Vector3d>& points);

}  // namespace mereo::features::detail
