// mereo/synthetic/scene.hpp: the built-in tabletop scene renderer and its exact ground truth.
//
// A scene is generated from a seed: floor, wall, a table with legs, and on the table mugs
// (hollow body, open top, a handle on the outer wall: a torus arc, or with handle_shapes
// "varied" also D-shaped, squared and flat-band handles), jars and cans (closed cylinders,
// upright or lying), bottles, plates, bowls and boxes, plus optional handle-like distractors
// beside jars and free-form distractors (blobs, bananas, drills, rounded boxes: model "other").
// Frames are ray cast analytically (no meshes), in parallel, with an optional depth noise model
// of a structured-light (Kinect) or an active-stereo (RealSense D4xx) camera.
// World frame: z up, origin at the centre of the table top.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"
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
  /// Rooms: the pixels it would cover with nothing in front of it, its own object's other parts
  /// included (a chair's seat seen from behind is hidden by its back); 0 for tabletop scenes.
  std::size_t unoccluded_pixels = 0;
};

struct ObjectTruth {
  std::uint32_t id = 0;              ///< value in GroundTruth::objects (1..N)
  std::string model;                 ///< "mug", "jar", "can", "bottle", "plate", "bowl",
                                     ///< "box", "cup", "table", "floor", "wall", "distractor",
                                     ///< "other" (free-form distractors: not to be recognized)
  std::string pose;                  ///< jars and cans: "upright" or "lying" (else empty)
  /// What kind of its model it is, where models come in kinds: a mug's handle ("torus", "d",
  /// "squared", "band") with handle_shapes "varied"; an "other": "blob", "banana", "drill",
  /// "rounded_box"; in rooms, a table: "dining" or "coffee", a chair: "office" or "four_legged", a
  /// door: "ajar" or "closed". Empty otherwise.
  std::string kind;
  std::vector<PartTruth> parts;
  std::size_t visible_pixels = 0;
  /// Rooms: the pixels it would cover with nothing in front of it (visible_pixels over this is the
  /// share of it in view that is not hidden); 0 for tabletop scenes (not computed).
  std::size_t unoccluded_pixels = 0;
  /// The camera-frame box of the visible surface points (exact depth), when any is visible:
  /// where an evaluation looks for results on an object that has no body to match.
  Eigen::Vector3d visible_min = Eigen::Vector3d::Zero(), visible_max = Eigen::Vector3d::Zero();
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

/// How Frame::depth is made from the exact depth (with SceneOptions::noise).
enum class DepthModel {
  Kinect,  ///< structured light (Kinect v1): axial noise, disparity steps, edge and shadow holes
  Stereo,  ///< active stereo (RealSense D4xx): StereoModel
};

/// The active-stereo depth model (SceneOptions::depth_model "stereo"): what an Intel RealSense
/// D435/D415 shows on a tabletop at 0.3-1.5 m, in the renderer's own intrinsics. A second
/// imager sits `baseline` to the right (+x) of the camera; depth comes from disparity
/// d = fx * baseline / z matched by a block matcher. Its errors, each from a parameter below:
///  - noise in disparity (so the depth error grows with z^2: sigma_z = sigma_d z^2 / (fx b)):
///    a smooth part, correlated over patches of `noise_patch` pixels (the matcher's window
///    and the projector's dot pattern make the surface of a flat wall wavy), and a small
///    per-pixel part; then disparity steps of 1/`subpixel` pixel;
///  - edge fattening: the matcher's window straddling a depth edge takes the foreground's
///    disparity, so the foreground bleeds 1..`fattening_px` pixels over the background on
///    its left (the side the second imager cannot see), the width varying along the edge;
///  - holes: background the second imager cannot see (left of near objects, beyond the
///    fattened strip); thin structures (under `thin_px` pixels across between two farther
///    surfaces: the window never fits on them); dark surfaces (too little texture and
///    projector return below `dark_albedo`), in patches; surfaces seen at grazing angles;
///    nothing nearer than `min_range` (the D435's minimum depth at full resolution) nor
///    farther than `max_range`.
struct StereoModel {
  /// Stereo baseline, metres. D435: 0.050; D415: 0.055.
  double baseline = 0.050;
  /// The smooth disparity error's standard deviation, pixels. With `pixel_noise_px` the
  /// total (~0.16 px, 6 mm/m^2 at fx 525) gives ~1.5 mm at 0.5 m and ~9 mm at 1.2 m, as
  /// measured D435 RMS errors are (Intel's ideal 0.08 px subpixel RMS is seldom reached on
  /// real surfaces; the datasheet allows 2% at 2 m).
  double patch_noise_px = 0.14;
  /// The per-pixel (uncorrelated) disparity error's standard deviation, pixels.
  double pixel_noise_px = 0.07;
  /// The smooth error's correlation length: the size of its patches, pixels.
  double noise_patch = 9.0;
  /// Disparity steps per pixel (D4xx: 5 subpixel bits, 1/32 pixel).
  double subpixel = 32.0;
  /// Nearest and farthest depth reported, metres (D435 at 848x480: ~0.28 m; its useful
  /// range indoors ends at a few metres).
  double min_range = 0.28;
  double max_range = 3.0;
  /// The widest strip of foreground depth over the background beside a depth edge, pixels
  /// (about half a 7x7 matching window).
  double fattening_px = 4.0;
  /// Structures narrower than this between two farther surfaces lose their depth (a pole,
  /// a handle seen far away), pixels; up to twice as wide, some of it.
  double thin_px = 4.0;
  /// Surfaces darker than this (luminance of the colour image, 0-1) start losing depth;
  /// at half of it, all of it.
  double dark_albedo = 0.10;
  static const Fields<StereoModel>& fields();
};

/// Mug handles: all torus arcs, or also D-shaped, squared and flat-band handles.
enum class HandleShapes { Torus, Varied };

struct SceneOptions {
  int width = 640;
  int height = 480;
  Intrinsics intrinsics = Intrinsics::kinect_vga();
  bool noise = true;                 ///< apply the depth model (and colour noise) to Frame
  /// The camera's depth errors with `noise`: Kinect-like (the default) or active stereo.
  DepthModel depth_model = DepthModel::Kinect;
  StereoModel stereo;                ///< the stereo model's parameters
  bool distractors = false;          ///< handle-like tori beside some jars
  /// ... touching the jar at its mid-height, the ring's plane turned 35-70 degrees away from
  /// the jar's axis: from some views it passes for a handle, from the views around not.
  bool ambiguous_distractors = false;
  /// Tapered cups (cone bodies, open at the wide top, 4-10 degrees) join the objects: one or
  /// two, after the others.
  bool tapered_cups = false;
  /// "varied": each mug's handle is a torus arc, D-shaped, squared or a flat band (a quarter
  /// each), spanning the same reach and height as the torus it replaces (the rest of the scene
  /// stays as with "torus").
  HandleShapes handle_shapes = HandleShapes::Torus;
  /// One or two cans or jars lying on their side (axis parallel to the table) join the objects.
  bool lying_containers = false;
  /// One to three free-form distractors join the objects: blobs (a few ellipsoids), bananas
  /// (a bent tube), drill-like shapes (boxes and a barrel), rounded boxes; model "other".
  bool freeform_distractors = false;
  /// A room instead of a tabletop (synthetic/room.cpp): floor, walls, a door (closed or ajar),
  /// tables, chairs (four-legged and office chairs) and a cabinet, seen from 2.5-4 m at a
  /// person's height; the tabletop's object and distance options do not apply.
  bool room = false;
  int min_objects = 3;               ///< objects on the table (besides distractors)
  int max_objects = 6;
  double min_distance = 0.6;         ///< camera distance to the table centre, metres
  double max_distance = 1.4;
  double min_elevation_deg = 25.0;   ///< camera looks down at this angle
  double max_elevation_deg = 60.0;
  double orbit_step_deg = 6.0;       ///< azimuth step per frame of a sequence
  /// Every option but the intrinsics, described once (Python's SceneOptions, the command
  /// line's scene flags).
  static const Fields<SceneOptions>& fields();
};

inline const Fields<StereoModel>& StereoModel::fields() {
  using S = StereoModel;
  static const Fields<S> f = {
      field("baseline", &S::baseline, 0.01, 0.5, "stereo baseline, metres"),
      field("patch_noise_px", &S::patch_noise_px, 0.0, 5.0, "smooth disparity noise (std), pixels"),
      field("pixel_noise_px", &S::pixel_noise_px, 0.0, 5.0, "per-pixel disparity noise (std), pixels"),
      field("noise_patch", &S::noise_patch, 1.0, 100.0, "size of the smooth noise's patches, pixels"),
      field("subpixel", &S::subpixel, 1.0, 1024.0, "disparity steps per pixel"),
      field("min_range", &S::min_range, 0.0, 10.0, "no depth nearer than this, metres"),
      field("max_range", &S::max_range, 0.1, 100.0, "no depth farther than this, metres"),
      field("fattening_px", &S::fattening_px, 0.0, 20.0, "widest foreground strip over the background, pixels"),
      field("thin_px", &S::thin_px, 0.0, 50.0, "structures narrower than this lose their depth, pixels"),
      field("dark_albedo", &S::dark_albedo, 0.0, 1.0, "surfaces darker than this lose depth, luminance 0-1"),
  };
  return f;
}

inline const Fields<SceneOptions>& SceneOptions::fields() {
  using O = SceneOptions;
  static const Fields<O> f = concat<O>(
      {
          field("width", &O::width, 1, 8192, "image width, pixels"),
          field("height", &O::height, 1, 8192, "image height, pixels"),
          field("noise", &O::noise, "depth (and colour) noise of the depth model; off: the exact depth"),
          choice("depth_model", &O::depth_model, {{"kinect", DepthModel::Kinect}, {"stereo", DepthModel::Stereo}},
                 "depth errors of a structured-light (Kinect) or an active-stereo (RealSense D4xx) camera"),
          field("distractors", &O::distractors, "handle-like tori beside some jars"),
          field("ambiguous_distractors", &O::ambiguous_distractors,
                "rings leaning on some jars (a mug's handle from some views)"),
          field("tapered_cups", &O::tapered_cups, "one or two tapered cups (cone bodies, 4-10 degrees) join the objects"),
          choice("handle_shapes", &O::handle_shapes, {{"torus", HandleShapes::Torus}, {"varied", HandleShapes::Varied}},
                 "mug handles: torus arcs, or also D-shaped, squared and flat-band ones"),
          field("lying_containers", &O::lying_containers, "one or two cans or jars lying on their side join the objects"),
          field("freeform_distractors", &O::freeform_distractors,
                "blobs, bananas, drills and rounded boxes join the objects (model 'other')"),
          field("room", &O::room, "a room with furniture (tables, chairs, a door, a cabinet) instead of a tabletop"),
          field("min_objects", &O::min_objects, 0, 50, "objects on the table (besides distractors), at least"),
          field("max_objects", &O::max_objects, 0, 50, "objects on the table (besides distractors), at most"),
          field("min_distance", &O::min_distance, 0.05, 20.0, "camera distance to the table centre, metres, at least"),
          field("max_distance", &O::max_distance, 0.05, 20.0, "camera distance to the table centre, metres, at most"),
          field("min_elevation_deg", &O::min_elevation_deg, 0.0, 89.0, "the camera looks down at least this much"),
          field("max_elevation_deg", &O::max_elevation_deg, 0.0, 89.0, "the camera looks down at most this much"),
          field("orbit_step_deg", &O::orbit_step_deg, -180.0, 180.0, "azimuth step per frame of a sequence"),
      },
      nested(&O::stereo, StereoModel::fields(), "stereo_"));
  return f;
}

/// One object placed in the world: its model name and its parts in the world frame.
struct SceneObject {
  std::string model;
  std::string pose;  ///< ObjectTruth::pose
  std::string kind;  ///< ObjectTruth::kind
  std::vector<std::pair<std::string, Shape>> parts;  ///< role, world-frame shape
  Eigen::Vector3f color = Eigen::Vector3f(0.6f, 0.6f, 0.6f);  ///< RGB in [0,1]
};

/// A generated scene (world frame) and the camera viewpoint of its first frame.
struct Scene {
  std::uint64_t seed = 0;
  bool room = false;                 ///< generated by generate_room
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

/// The scene of a seed (deterministic: the same seed gives the same scene on any machine): a
/// tabletop, or with options.room a room (generate_room).
Scene generate_scene(std::uint64_t seed, const SceneOptions& options = {});

/// A room of a seed (synthetic/room.cpp): world z up, the floor at z = 0; objects "floor", "wall",
/// "door" (part "leaf"), "table" ("top", legs), "chair" ("seat", "back", legs or a column and a
/// base), "cabinet" ("body").
Scene generate_room(std::uint64_t seed, const SceneOptions& options = {});

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
