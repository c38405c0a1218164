// Internal: the shape builders the scene generators share (scene.cpp: the tabletop, room.cpp: rooms).
#pragma once

#include <string>

#include <Eigen/Core>

#include "mereo/synthetic/scene.hpp"
#include "raycast.hpp"

namespace mereo::synthetic::detail {

/// A box standing upright: centre, yaw of its local x about z, full extents.
Shape box(const Vec3& centre, double yaw, const Vec3& size);
/// An unbounded plane (floor, wall) through `point`.
Shape plane(const Vec3& point, const Vec3& normal);
/// A saturated-ish random colour (RGB in [0, 1]).
Eigen::Vector3f random_color(Rng& rng);
/// A rotation: yaw about z, then pitch about y, then roll about x (each of the local frame).
Eigen::Matrix3d rotation(double yaw, double pitch, double roll);
/// A box, ellipsoid or rounded box of class `cls` with local axes R's columns and full extents `size`.
Shape oriented(const std::string& cls, const Vec3& centre, const Eigen::Matrix3d& R, const Vec3& size);

}  // namespace mereo::synthetic::detail
