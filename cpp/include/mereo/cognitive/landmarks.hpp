// mereo/cognitive/landmarks.hpp: the camera's pose from the scene's own primitives: the table
// plane, the upright cylinders standing on it (mug, cup, jar, can and bottle bodies) and the
// rings beside them (handles), held in a small map in the world frame.
//
// The table plane fixes three of the pose's six degrees of freedom (tilt and height); the
// upright cylinders' axes, where they meet the table, and the rings' centres, dropped onto it,
// are points in the table's plane that fix the other three (the turn about the table's normal
// and the slide along it). A plane and one cylinder leave the turn about the cylinder's axis
// free (frame-to-frame ICP drifts there); its handle fixes it. The frame's points are matched to
// the map's by RANSAC over pairs (two matches give the planar motion; classes and radii must
// agree, pair distances must agree), scored by how many points land on a landmark; the best
// motion is refitted to all its matches (2-D Procrustes, a ring's centre weighing less than an
// axis: it is fitted less precisely). Unlike frame-to-frame
// odometry it cannot slide along an untextured table, and it does not accumulate drift while the
// same landmarks stay in view. Odometry (cognitive::Odometry) uses it to correct its estimate.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/camera.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/features/handle.hpp"

namespace mereo::cognitive {

struct LandmarkOptions {
  double max_tilt_deg = 10.0;        ///< a cylinder is upright when its axis is this close to the normal
  double min_radius = 0.015;         ///< metres
  double max_radius = 0.15;
  std::size_t min_inliers = 150;     ///< pixels of a cylinder used as a landmark
  std::size_t min_ring_inliers = 100; ///< pixels of a ring (torus) used as a landmark
  features::HandleOptions handle;     ///< what a handle (a ring used as a landmark) is
  double ring_weight = 0.1;          ///< a ring's centre in the fit, against an axis's 1 (its error is ~3x)
  double ring_turn_tolerance_deg = 3.0; ///< with fewer than two axes, the guess's turn stays within this of the rings'
  double match_distance = 0.015;     ///< metres, in the table's plane
  double radius_tolerance = 0.006;   ///< metres, plus 10% of the radius
  double max_plane_angle_deg = 20.0; ///< the frame's table may differ this much from the map's
  double max_plane_offset = 0.15;    ///< metres (under the guessed pose): else it is not the table
};

/// A table plane in some frame: normal.dot(x) + d = 0, normal up (towards the camera), d > 0
/// above the table.
struct TablePlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0.0;
};

struct Landmark {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  ///< where the axis meets the table, table coordinates
  double radius = 0.0;
  PrimitiveClass cls = PrimitiveClass::of<shapes::Cylinder>();  ///< a cylinder's axis or a ring's (torus) centre
  int views = 0;
};

/// The map: the world's table plane and the landmarks on it (2-D table coordinates: origin the
/// world origin's foot on the table, x the world's x projected on it).
struct LandmarkMap {
  std::optional<TablePlane> table;  ///< world frame
  std::vector<Landmark> landmarks;
};

/// A landmark of a frame in the frame's table coordinates: an upright cylinder where its axis
/// meets the table, a ring's centre dropped onto it.
struct PlanarPoint {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double radius = 0.0;  ///< a ring's: its major radius
  PrimitiveClass cls = PrimitiveClass::of<shapes::Cylinder>();
  double weight = 1.0;  ///< in the fit
};

struct LandmarkFix {
  Pose camera_to_world = Pose::Identity();
  int matched = 0;    ///< points matched to landmarks under this pose
  int observed = 0;   ///< landmark points in the frame (upright cylinders, rings)
  bool plane = false; ///< the frame's table was used (tilt and height from it)
};

/// The table coordinates of a frame: a rigid transform taking `plane` to z = 0 with its normal
/// to +z, the frame's x axis projected on the plane to +x.
Pose table_from(const TablePlane& plane);

/// The frame's landmark points in its table coordinates: its upright cylinders (outward,
/// `min_inliers`) where their axes meet `plane`, its handle-sized rings (`min_ring_inliers`)
/// where their centres drop onto it.
std::vector<PlanarPoint> landmark_points(const std::vector<Segment>& segments, const TablePlane& plane,
                                           const LandmarkOptions& options = {});

/// The pose of a frame (its table plane, camera frame, and its segments) against `map`, starting
/// from `guess` (camera to world). Without a usable table (none, or too far from the map's under
/// the guess) it returns the guess with `plane` false. Two matched axes fix the turn about the
/// normal; with fewer, it is the guess's, kept within `ring_turn_tolerance_deg` of the turn that
/// the matched rings give (a ring's centre is fitted less precisely than an axis); one match
/// still fixes the slide.
LandmarkFix locate(const LandmarkMap& map, const TablePlane& plane, const std::vector<Segment>& segments,
                   const Pose& guess, const LandmarkOptions& options = {});

/// Adds the frame's landmark points to `map` under `camera_to_world` (a match refines its
/// landmark's running mean, a new point becomes a landmark); the first call sets the map's
/// table.
void add_to_map(LandmarkMap& map, const TablePlane& plane, const std::vector<Segment>& segments,
                const Pose& camera_to_world, const LandmarkOptions& options = {});

}  // namespace mereo::cognitive
