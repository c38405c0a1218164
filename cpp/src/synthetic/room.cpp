// The synthetic room (SceneOptions::room): furniture with exact ground truth, for the room graph.
//
// World frame: z up, the floor at z = 0, the furniture about the origin. A back wall (y = +Y)
// with a door in it (an opening with the leaf closed a few centimetres in, or ajar, the room
// beyond), a side wall, a dining or coffee table, chairs around it (four-legged ones with a
// straight or leaning back, or office chairs on a column and a five-star base), sometimes a
// chair on its own, and a cabinet against a wall. Sizes from real furniture (EN 1335 office
// chairs, dining tables 0.72-0.76 m, coffee tables 0.40-0.48 m, doors 0.8-0.95 x 2.0-2.1 m).
// The camera stands 2.5-4 m from the table at a person's height (1.2-1.7 m), looking at it.
#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "mereo/synthetic/scene.hpp"
#include "raycast.hpp"
#include "scene_build.hpp"

namespace mereo::synthetic {
namespace {

using namespace detail;
constexpr double kPi = 3.14159265358979323846;

/// A muted furniture or wall colour: wood, grey, white, dark.
Eigen::Vector3f furniture_color(Rng& rng) {
  switch (rng.integer(0, 3)) {
    case 0: return Eigen::Vector3f(float(rng.uniform(0.55, 0.75)), float(rng.uniform(0.35, 0.5)), float(rng.uniform(0.18, 0.3)));
    case 1: { const float g = float(rng.uniform(0.35, 0.6)); return Eigen::Vector3f(g, g, g * 1.05f); }
    case 2: { const float g = float(rng.uniform(0.8, 0.95)); return Eigen::Vector3f(g, g, g * 0.97f); }
    default: return random_color(rng) * 0.6f;
  }
}

/// Four square legs of side `leg` standing on the floor under `at` (turned by R) at (+-lx, +-ly),
/// `height` tall: a table's or a chair's.
void add_legs(SceneObject& o, const Vec3& at, const Eigen::Matrix3d& R, double lx, double ly, double leg, double height) {
  const double sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
  for (int i = 0; i < 4; ++i)
    o.parts.emplace_back("leg" + std::to_string(i + 1), oriented("box", at + R * Vec3(sx[i] * lx, sy[i] * ly, 0) + Vec3(0, 0, 0.5 * height),
                                                                 R, Vec3(leg, leg, height)));
}

/// A table: a top at `height` (its upper face), `length` x `width`, on four legs, turned by `yaw`.
SceneObject table(Rng& rng, const Vec3& at, double yaw, double length, double width, double height) {
  SceneObject t;
  t.model = "table";
  t.color = furniture_color(rng);
  const double top = rng.uniform(0.02, 0.04), leg = rng.uniform(0.035, 0.06), inset = rng.uniform(0.03, 0.08);
  const Eigen::Matrix3d R = rotation(yaw, 0, 0);
  t.parts.emplace_back("top", oriented("box", at + Vec3(0, 0, height - 0.5 * top), R, Vec3(length, width, top)));
  add_legs(t, at, R, 0.5 * length - inset - 0.5 * leg, 0.5 * width - inset - 0.5 * leg, leg, height - top);
  return t;
}

/// A chair facing `facing` (a horizontal direction: where a sitter looks), its seat centred over `at`.
SceneObject chair(Rng& rng, const Vec3& at, double facing, bool office) {
  SceneObject c;
  c.model = "chair";
  c.kind = office ? "office" : "four_legged";
  c.color = furniture_color(rng);
  const double sw = rng.uniform(0.40, 0.50), sd = rng.uniform(0.38, 0.48), st = rng.uniform(0.03, 0.07);
  const double sh = rng.uniform(0.42, 0.50);  // the seat's upper face
  const double bh = rng.uniform(0.32, 0.50), bt = rng.uniform(0.02, 0.05), lean = rng.uniform(0.0, 15.0) * kPi / 180;
  const double gap = office ? rng.uniform(0.05, 0.12) : 0.0;
  // local frame: x across the seat, y the way the sitter looks, z up
  const Eigen::Matrix3d R = rotation(facing - kPi / 2, 0, 0);
  c.parts.emplace_back("seat", oriented("box", at + Vec3(0, 0, sh - 0.5 * st), R, Vec3(sw, sd, st)));
  // the back rises from the seat's rear edge, leaning back by `lean` (about the local x axis)
  const Eigen::Matrix3d Rb = R * Eigen::AngleAxisd(lean, Vec3::UnitX()).toRotationMatrix();
  const Vec3 rear = at + R * Vec3(0, -0.5 * sd + 0.5 * bt, 0) + Vec3(0, 0, sh + gap);
  c.parts.emplace_back("back", oriented("box", rear + Rb * Vec3(0, 0, 0.5 * bh), Rb, Vec3(sw * rng.uniform(0.85, 1.0), bt, bh)));
  if (office) {
    Shape column;
    column.cls = "cylinder";
    column.point = at + Vec3(0, 0, 0.5 * (sh - st + 0.08));
    column.axis = Vec3::UnitZ();
    column.radius = 0.025;
    column.height = sh - st - 0.08;
    c.parts.emplace_back("column", column);
    for (int k = 0; k < 5; ++k) {
      const double a = facing + 2 * kPi * k / 5;
      c.parts.emplace_back("base" + std::to_string(k + 1),
                           oriented("box", at + Vec3(0.15 * std::cos(a), 0.15 * std::sin(a), 0.05), rotation(a, 0, 0),
                                    Vec3(0.3, 0.04, 0.04)));
    }
    // the back's post from the seat's rear
    c.parts.emplace_back("post", oriented("box", at + R * Vec3(0, -0.5 * sd + 0.5 * bt, 0) + Vec3(0, 0, sh + 0.5 * gap), R,
                                          Vec3(0.05, bt, gap + 0.01)));
  } else {
    const double leg = rng.uniform(0.025, 0.04);
    add_legs(c, at, R, 0.5 * sw - 0.5 * leg, 0.5 * sd - 0.5 * leg, leg, sh - st);
  }
  return c;
}

}  // namespace

Scene generate_room(std::uint64_t seed, const SceneOptions& options) {
  Rng rng(seed ^ 0x526F6F6D5365ull);  // "RoomSe": a stream apart from the tabletop's
  Scene scene;
  scene.seed = seed;
  scene.room = true;

  // the table and the view of it
  const bool dining = rng.chance(0.7);
  const double L = dining ? rng.uniform(0.9, 1.8) : rng.uniform(0.8, 1.2);
  const double W = dining ? rng.uniform(0.6, 1.0) : rng.uniform(0.45, 0.7);
  const double H = dining ? rng.uniform(0.72, 0.76) : rng.uniform(0.40, 0.48);
  const double yaw = rng.uniform(-0.4, 0.4);
  scene.look_at = Vec3(0, 0, 0.45);
  scene.camera_distance = rng.uniform(2.5, 4.0);
  const double eye = rng.uniform(1.2, 1.7);
  scene.camera_elevation_deg = std::asin((eye - scene.look_at.z()) / scene.camera_distance) * 180 / kPi;
  scene.camera_azimuth_deg = -90 + rng.uniform(-35.0, 35.0);

  // floor and walls: the back wall behind the table with a door in it, a side wall
  const double back = 0.5 * W + rng.uniform(1.3, 2.0);  // y of the back wall's face: behind the chairs
  const double side = rng.uniform(2.5, 3.5) * (rng.chance(0.5) ? 1 : -1);
  const Eigen::Vector3f wall_color(float(rng.uniform(0.75, 0.92)), float(rng.uniform(0.72, 0.9)), float(rng.uniform(0.65, 0.85)));
  {
    SceneObject floor;
    floor.model = "floor";
    const double g = rng.uniform(0.3, 0.5);
    floor.color = Eigen::Vector3f(float(g), float(g * rng.uniform(0.9, 1.05)), float(g * rng.uniform(0.85, 1.0)));
    floor.parts.emplace_back("plane", plane(Vec3::Zero(), Vec3::UnitZ()));
    scene.objects.push_back(std::move(floor));
  }
  const double door_w = rng.uniform(0.8, 0.95), door_h = rng.uniform(2.0, 2.1);
  const double door_x = rng.uniform(-1.2, 1.2), thick = 0.12;
  {
    // the back wall as three boxes about the door's opening, the room beyond it a plane
    SceneObject wall;
    wall.model = "wall";
    wall.color = wall_color;
    const double x0 = door_x - 0.5 * door_w, x1 = door_x + 0.5 * door_w, far = 8.0, top = 3.0;
    const double y = back + 0.5 * thick;
    wall.parts.emplace_back("left", box(Vec3(0.5 * (x0 - far), y, 0.5 * top), 0, Vec3(x0 + far, thick, top)));
    wall.parts.emplace_back("right", box(Vec3(0.5 * (x1 + far), y, 0.5 * top), 0, Vec3(far - x1, thick, top)));
    wall.parts.emplace_back("lintel", box(Vec3(door_x, y, 0.5 * (door_h + top)), 0, Vec3(door_w, thick, top - door_h)));
    scene.objects.push_back(std::move(wall));
    SceneObject beyond;
    beyond.model = "wall";
    beyond.color = wall_color * 0.8f;
    beyond.parts.emplace_back("plane", plane(Vec3(0, back + rng.uniform(1.5, 3.0), 0), -Vec3::UnitY()));
    scene.objects.push_back(std::move(beyond));
    SceneObject side_wall;
    side_wall.model = "wall";
    side_wall.color = wall_color * 0.95f;
    side_wall.parts.emplace_back("plane", plane(Vec3(side, 0, 0), Vec3(side > 0 ? -1 : 1, 0, 0)));
    scene.objects.push_back(std::move(side_wall));
  }
  {
    // the leaf: closed 2-5 cm into the opening, or ajar 20-90 degrees into the room, hinged at
    // the opening's left or right edge
    SceneObject door;
    door.model = "door";
    door.color = rng.chance(0.5) ? Eigen::Vector3f(0.6f, 0.42f, 0.25f) : Eigen::Vector3f(0.92f, 0.92f, 0.9f);
    const double lt = 0.04, lw = door_w - 0.01, lh = door_h - 0.01;
    const bool ajar = rng.chance(0.5);
    const double hinge_side = rng.chance(0.5) ? -1.0 : 1.0;
    const double angle = ajar ? rng.uniform(20.0, 90.0) * kPi / 180 : 0.0;
    const double inset = ajar ? 0.0 : rng.uniform(0.02, 0.05);
    door.kind = ajar ? "ajar" : "closed";
    const Vec3 hinge(door_x + hinge_side * 0.5 * door_w, back + inset + 0.5 * lt, 0);
    // the leaf's centre from the hinge: across the opening, turned into the room (-y)
    const double a = hinge_side > 0 ? kPi + angle : -angle;
    const Vec3 across(std::cos(a), std::sin(a), 0);
    door.parts.emplace_back("leaf", oriented("box", hinge + 0.5 * lw * across + Vec3(0, 0, 0.5 * lh + 0.005),
                                             rotation(a, 0, 0), Vec3(lw, lt, lh)));
    scene.objects.push_back(std::move(door));
  }
  // the table, chairs about it (at its long sides, facing it, pulled out), a chair on its own
  scene.objects.push_back(table(rng, Vec3::Zero(), yaw, L, W, H));
  scene.objects.back().kind = dining ? "dining" : "coffee";
  const Eigen::Matrix3d Ry = rotation(yaw, 0, 0);
  const bool office = rng.chance(0.4);
  const int per_side = dining ? std::max(1, int(L / 0.6)) : 0;
  for (int side_k = 0; side_k < 2; ++side_k)
    for (int k = 0; k < per_side; ++k) {
      if (rng.chance(0.3)) continue;
      const double sgn = side_k ? 1.0 : -1.0;
      const double x = (per_side == 1 ? 0.0 : -0.5 * L + 0.3 + k * (L - 0.6) / (per_side - 1)) + rng.uniform(-0.05, 0.05);
      const double pull = 0.5 * W + rng.uniform(0.05, 0.3);
      const Vec3 at = Ry * Vec3(x, sgn * pull, 0);
      const double facing = yaw + (sgn > 0 ? -kPi / 2 : kPi / 2) + rng.uniform(-0.3, 0.3);
      scene.objects.push_back(chair(rng, at, facing, office));
    }
  if (!dining || rng.chance(0.5)) {
    const double sgn = rng.chance(0.5) ? 1.0 : -1.0;
    const Vec3 at(sgn * (0.5 * L + rng.uniform(0.6, 1.0)), rng.uniform(-0.6, 0.4), 0);
    scene.objects.push_back(chair(rng, at, rng.uniform(0.0, 2 * kPi), rng.chance(0.5)));
  }
  {
    // a cabinet against the back wall, away from the door
    SceneObject cab;
    cab.model = "cabinet";
    cab.color = furniture_color(rng);
    const double cw = rng.uniform(0.5, 1.0), cd = rng.uniform(0.35, 0.5), ch = rng.uniform(0.8, 1.9);
    const double cx = door_x > 0 ? door_x - 0.5 * door_w - 0.2 - rng.uniform(0.6, 1.4) : door_x + 0.5 * door_w + 0.2 + rng.uniform(0.6, 1.4);
    cab.parts.emplace_back("body", box(Vec3(cx, back - 0.5 * cd, 0.5 * ch), 0, Vec3(cw, cd, ch)));
    scene.objects.push_back(std::move(cab));
  }
  return scene;
}

}  // namespace mereo::synthetic
