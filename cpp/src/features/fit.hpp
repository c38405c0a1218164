// Internal: least-squares refits of the feature layer (features/primitives.hpp): Levenberg-
// Marquardt on a shape's packed parameters (mereo/shapes/), residuals along the rays, visible
// extents. Metres, camera frame.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/segment.hpp"

namespace mereo::features::detail {

/// At most `max_points` of `points`, evenly strided (deterministic): `points` itself when it has
/// no more, else `buffer`, filled with them.
const std::vector<Eigen::Vector3d>& subsample_into(const std::vector<Eigen::Vector3d>& points,
                                                   std::vector<Eigen::Vector3d>& buffer, std::size_t max_points);

/// A least-squares fit of a few parameters gains nothing from thousands of points but time.
constexpr std::size_t kFitPoints = 600;

/// Levenberg-Marquardt on the residuals f(x) (N of them), numerical Jacobian; x is updated.
void levenberg_marquardt(Eigen::VectorXd& x, int N,
                         const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& f);

/// What a least-squares refit minimises.
///  - Geometric: the distance of each point to the surface.
///  - AlongRay: camera-frame points: the shape's range_residual (curved classes: each point's
///    range minus the range at which its pixel's ray meets the surface; a depth sensor's noise lies
///    along the ray, so this is the maximum-likelihood fit, where the geometric one shrinks a
///    cylinder's radius by up to 1 mm at 1.5 m); other classes: geometric.
enum class Residual { Geometric, AlongRay };

/// The shape refined to the points: its closed-form fit where it has one (planes: PCA), else
/// Levenberg-Marquardt on `residual` from `s` (its Jacobian in closed form where the class gives
/// the range residual's gradient: cylinders, spheres). Sets residual (RMS of the geometric distance).
Segment refit_points(const Segment& s, const std::vector<Eigen::Vector3d>& points,
                     Residual residual = Residual::Geometric);

/// residual = RMS of the points' signed distances to s.
void set_residual(Segment& s, const std::vector<Eigen::Vector3d>& points);

/// The shape's visible extent from its inliers (a cylinder's centre and height, a plane's
/// centroid); others unchanged.
void set_extent(Segment& s, const std::vector<Eigen::Vector3d>& points);

}  // namespace mereo::features::detail
