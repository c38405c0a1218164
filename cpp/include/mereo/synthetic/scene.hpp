// mereo/synthetic/scene.hpp: the built-in tabletop scene renderer and its exact ground truth.
//
// A scene is generated from a seed: floor, wall, a table with legs, and on the table mugs
// (hollow body, open top, torus handle on the outer wall), jars and cans (closed cylinders),
// bottles, plates, bowls and boxes, plus optional handle-like distractors beside jars.
// Frames are ray cast analytically (no meshes), in parallel, with an optional Kinect-like
// noise model. World frame: z up, origin at the centre of the table top.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/frame.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::synthetic {

/// The parameters of one part's shape. Which fields mean something depends on `cls`:
///  - "cylinder": `point` on the axis at the middle of the part, unit `axis`, `radius`, `height`
///    (a closed cylinder's caps and a mug's inner wall are parts of their own);
///  - "cone":     a truncated cone: `point` on the axis at the middle of the part, unit `axis`
///    the way it widens, `radius` at `point`, half-angle `angle` (radians), `height`;
///  - "torus":    `point` = centre, `axis` = unit normal of the ring plane (the symmetry axis),
///    `radius` = major radius, `minor_radius`; only the arc outside a mug body is rendered,
///    `arc_start`/`arc_end` bound the visible arc (radians, see scene.cpp);
///  - "disc":     a flat annulus: `point` = centre, `axis` = normal, `radius` = outer radius,
///    `minor_radius` = inner radius (0 for a full disc);
///  - "sphere":   `point` = centre, `radius` (bowls: the zone between two planes normal to
///    `axis`, at signed offsets `height_min`..`height_max` from the centre);
///  - "box":      `point` = centre, `axis` = local z, `axis2` = local x, `size` = full extents;
///  - "plane":    `point` on it, `axis` = normal (floor and wall; unbounded);
///  - "ellipsoid": `point` = centre, `axis` = local z, `axis2` = local x, `size` = full extents
///    (twice the semi-axes) along local x, y, z;
///  - "rounded_box": a box with rounded edges and corners (the points within `radius` of an
///    inner box): `point`, `axis`, `axis2`, `size` as "box" (the outer extents), `radius`;
///  - "loop":     a tube of radius `minor_radius` swept along a rounded rectangle in the plane
///    through `point` normal to `axis`: `point` = the rectangle's centre, `axis2` = the
///    direction of its first side (a handle's: away from the body), `size.x()` and `size.y()`
///    = the centre line's extents along `axis2` and along `axis x axis2`, `radius` = the centre
///    line's corner radius (minor_radius < radius <= half of either extent; a circle when
///    both halves equal it). D-shaped handles have large corners, squared ones small;
///  - "band":     a flat strip along the same rounded rectangle: a rectangular cross-section
///    `2 minor_radius` thick in the plane and `height` wide along `axis` (edge-on when seen
///    along `axis`).
/// A mug's handle ("torus", "loop" or "band") is rendered only outside its body's outer
/// cylinder: the ends that go into the wall are hidden.
struct Shape {
  std::string cls;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  double radius = 0.0;
  double height = 0.0;
  double minor_radius = 0.0;
  double angle = 0.0;  ///< "cone": half-angle, radians
  double height_min = 0.0;
  double height_max = 0.0;
  double arc_start = 0.0;
  double arc_end = 0.0;
  bool inward = false;  ///< surface normal points towards the axis / centre (inner walls)

  /// The same shape in another frame (points move, directions rotate).
  Shape transformed(const Pose& T) const;
  /// The segment of exactly this shape, for a class of the shape table (mereo/shapes/table.hpp);
  /// nullopt for the renderer's own ("disc", "box").
  std::optional<Segment> segment() const;
};

/// One part of a rendered object (a mug's "body", "inside", "rim", "bottom", "handle").
struct PartTruth {
  std::string role;
  Shape world;                       ///< parameters in the world frame
  Shape camera;                      ///< the same in the camera frame of this frame
  std::uint32_t label = 0;           ///< value in GroundTruth::parts (unique per frame)
  std::size_t visible_pixels = 0;    ///< pixels of this part in the clean render
};

struct ObjectTruth {
  std::uint32_t id = 0;              ///< value in GroundTruth::objects (1..N)
  std::string model;                 ///< "mug", "jar", "can", "bottle", "plate", "bowl",
                                     ///< "box", "table", "floor", "wall", "distractor"
  std::vector<PartTruth> parts;
  std::size_t visible_pixels = 0;
  const PartTruth* part(const std::string& role) const;
};

/// Exact ground truth of one rendered frame (before noise).
struct GroundTruth {
  DepthImage depth;       ///< clean depth, metres, NaN where no surface
  NormalMap normals;      ///< analytic unit normals, camera frame, towards the camera
  LabelImage objects;     ///< ObjectTruth::id per pixel, 0 = nothing
  LabelImage parts;       ///< PartTruth::label per pixel, 0 = nothing
  std::vector<ObjectTruth> objects_truth;
  Pose camera_pose = Pose::Identity();  ///< camera-to-world
  const ObjectTruth* object(std::uint32_t id) const;
};

struct SceneOptions {
  int width = 640;
  int height = 480;
  Intrinsics intrinsics = Intrinsics::kinect_vga();
  bool noise = true;                 ///< apply the Kinect-like noise model to Frame::depth
  bool distractors = false;          ///< handle-like tori beside some jars
  /// ... touching the jar at its mid-height, the ring's plane turned 35-70 degrees away from
  /// the jar's axis: from some views it passes for a handle, from the views around not.
  bool ambiguous_distractors = false;
  /// Tapered cups (cone bodies, open at the wide top, 4-10 degrees) join the objects: one or
  /// two, after the others.
  bool tapered_cups = false;
  int min_objects = 3;               ///< objects on the table (besides distractors)
  int max_objects = 6;
  double min_distance = 0.6;         ///< camera distance to the table centre, metres
  double max_distance = 1.4;
  double min_elevation_deg = 25.0;   ///< camera looks down at this angle
  double max_elevation_deg = 60.0;
  double orbit_step_deg = 6.0;       ///< azimuth step per frame of a sequence
};

/// One object placed in the world: its model name and its parts in the world frame.
struct SceneObject {
  std::string model;
  std::vector<std::pair<std::string, Shape>> parts;  ///< role, world-frame shape
  Eigen::Vector3f color = Eigen::Vector3f(0.6f, 0.6f, 0.6f);  ///< RGB in [0,1]
};

/// A generated scene (world frame) and the camera viewpoint of its first frame.
struct Scene {
  std::uint64_t seed = 0;
  std::vector<SceneObject> objects;  ///< floor, wall and table first
  double camera_distance = 1.0;
  double camera_elevation_deg = 40.0;
  double camera_azimuth_deg = 0.0;
  Eigen::Vector3d look_at = Eigen::Vector3d::Zero();
};

struct SyntheticFrame {
  Frame frame;         ///< colour, (noisy) depth, intrinsics, pose, id, source "synthetic:SEED"
  GroundTruth truth;
};

/// The scene of a seed (deterministic: the same seed gives the same scene on any machine).
Scene generate_scene(std::uint64_t seed, const SceneOptions& options = {});

/// Camera-to-world pose looking at `look_at` from `distance`, elevation and azimuth.
Pose orbit_pose(const Eigen::Vector3d& look_at, double distance, double elevation_deg,
                double azimuth_deg);

/// The camera pose of frame `frame_index` of the scene's orbit: the scene's first viewpoint
/// turned by frame_index * options.orbit_step_deg of azimuth about the table (views.cpp).
Pose orbit_view(const Scene& scene, int frame_index, const SceneOptions& options);

/// Renders one frame of `scene` from `camera_pose` (parallel over rows; deterministic).
SyntheticFrame render(const Scene& scene, const Pose& camera_pose, const SceneOptions& options,
                      int frame_index = 0);

/// The first frame of the scene of `seed`.
SyntheticFrame render(std::uint64_t seed, const SceneOptions& options = {});

/// `frames` frames of the scene of `seed`, the camera orbiting the table by
/// options.orbit_step_deg per frame; each frame carries its pose.
std::vector<SyntheticFrame> render_sequence(std::uint64_t seed, int frames,
                                            const SceneOptions& options = {});

/// The ground truth as JSON text (intrinsics, camera pose, objects with their parts in the
/// camera and world frames, visible pixels). Images are not included.
std::string truth_to_json(const SyntheticFrame& f);

}  // namespace mereo::synthetic
