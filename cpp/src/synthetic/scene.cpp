// The synthetic tabletop scene: generation from a seed, the orbit camera, ground-truth JSON.
//
// World frame: z up, origin at the centre of the table top (the top surface is z = 0).
// All objects stand on the table top. Shapes are described by mereo::synthetic::Shape:
//  - a cylinder's `point` is on its axis at the middle of the part, `height` its full length;
//  - a torus's arc is measured in its ring plane from `axis2` (angle 0) towards
//    `axis x axis2` (angle +pi/2); the rendered part is arc_start <= angle <= arc_end
//    (arc_end <= arc_start means the full ring). A mug handle's `axis2` points away from the
//    body axis and its arc is the part of the ring's centre circle outside the body's outer
//    radius; the renderer also hides every point of the tube inside the body cylinder.
//    A distractor's arc is [0, pi]: the upper half ring standing on the table.
//  - a varied handle ("loop", "band") lies in the same plane as the torus it replaces and spans
//    the same reach from the wall and about its height; its rounded rectangle reaches 3 mm
//    into the wall, where the renderer hides it.
// Objects stand on the table top, except lying cans and jars (their axis horizontal, resting on
// their side) and the free-form distractors (resting on their lowest point).
#include "mereo/synthetic/scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "mereo/core/error.hpp"
#include "raycast.hpp"
#include "scene_build.hpp"
#include "shapes/json.hpp"

namespace mereo::synthetic {

using detail::Rng;
using detail::Vec3;

std::optional<Segment> Shape::segment() const {
  const auto names = primitive_class_names();
  if (std::find(names.begin(), names.end(), cls) == names.end()) return std::nullopt;
  Segment s(primitive_class(cls).make());
  // the renderer's fields by their common names; a class takes those it has (set_field's aliases)
  s.set_field("point", point);
  s.set_field("axis", Eigen::Vector3d(axis.normalized()));
  s.set_field("radius", radius);
  s.set_field("height", height);
  s.set_field("minor_radius", minor_radius);
  s.set_field("d", -axis.normalized().dot(point));  // a plane's
  s.set_field("half_angle_deg", angle * 180.0 / 3.14159265358979323846);  // a cone's
  s.inward = inward;
  return s;
}

Shape Shape::transformed(const Pose& T) const {
  Shape s = *this;
  s.point = T * point;
  s.axis = (T.linear() * axis).normalized();
  s.axis2 = (T.linear() * axis2).normalized();
  return s;
}

const PartTruth* ObjectTruth::part(const std::string& role) const {
  for (const auto& p : parts)
    if (p.role == role) return &p;
  return nullptr;
}

const ObjectTruth* GroundTruth::object(std::uint32_t id) const {
  for (const auto& o : objects_truth)
    if (o.id == id) return &o;
  return nullptr;
}

Pose orbit_pose(const Eigen::Vector3d& look_at, double distance, double elevation_deg,
                double azimuth_deg) {
  constexpr double deg = 3.14159265358979323846 / 180.0;
  const double el = elevation_deg * deg, az = azimuth_deg * deg;
  const Vec3 pos = look_at + distance * Vec3(std::cos(el) * std::cos(az),
                                             std::cos(el) * std::sin(az), std::sin(el));
  const Vec3 z = (look_at - pos).normalized();  // forward
  Vec3 x = z.cross(Vec3::UnitZ());              // right (horizontal: no roll)
  if (x.norm() < 1e-9) x = Vec3::UnitX();       // looking straight down
  x.normalize();
  const Vec3 y = z.cross(x);  // down
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = pos;
  return T;
}

namespace detail {

Shape box(const Vec3& centre, double yaw, const Vec3& size) {
  Shape s;
  s.cls = "box";
  s.point = centre;
  s.axis = Vec3::UnitZ();
  s.axis2 = Vec3(std::cos(yaw), std::sin(yaw), 0.0);
  s.size = size;
  return s;
}

Shape plane(const Vec3& point, const Vec3& normal) {
  Shape s;
  s.cls = "plane";
  s.point = point;
  s.axis = normal.normalized();
  return s;
}

Eigen::Vector3f random_color(Rng& rng) {
  // a saturated-ish random colour: random hue, saturation 0.35-0.9, value 0.35-0.95
  const double h = rng.uniform(0.0, 6.0), s = rng.uniform(0.35, 0.9), v = rng.uniform(0.35, 0.95);
  const int i = std::min(5, int(h));
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  return Eigen::Vector3f(float(r), float(g), float(b));
}

/// A rotation: yaw about z, then pitch about y, then roll about x (each of the local frame).
Eigen::Matrix3d rotation(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
          Eigen::AngleAxisd(roll, Vec3::UnitX()))
      .toRotationMatrix();
}

Shape oriented(const std::string& cls, const Vec3& centre, const Eigen::Matrix3d& R, const Vec3& size) {
  Shape s;
  s.cls = cls;
  s.point = centre;
  s.axis = R.col(2);
  s.axis2 = R.col(0);
  s.size = size;
  return s;
}

}  // namespace detail

namespace {

using namespace detail;

constexpr double kPi = 3.14159265358979323846;

Shape cylinder(double x, double y, double z0, double z1, double r, bool inward = false) {
  Shape s;
  s.cls = "cylinder";
  s.point = Vec3(x, y, 0.5 * (z0 + z1));
  s.axis = Vec3::UnitZ();
  s.radius = r;
  s.height = z1 - z0;
  s.inward = inward;
  return s;
}

/// A truncated cone about the vertical through (x, y), radius r0 at z0 and r1 > r0 at z1.
Shape cone(double x, double y, double z0, double z1, double r0, double r1, bool inward = false) {
  Shape s;
  s.cls = "cone";
  s.point = Vec3(x, y, 0.5 * (z0 + z1));
  s.axis = Vec3::UnitZ();
  s.radius = 0.5 * (r0 + r1);
  s.height = z1 - z0;
  s.angle = std::atan((r1 - r0) / (z1 - z0));
  s.inward = inward;
  return s;
}

Shape disc(double x, double y, double z, double r_out, double r_in = 0.0, bool down = false) {
  Shape s;
  s.cls = "disc";
  s.point = Vec3(x, y, z);
  s.axis = down ? Vec3(-Vec3::UnitZ()) : Vec3(Vec3::UnitZ());
  s.radius = r_out;
  s.minor_radius = r_in;
  return s;
}




struct Footprint {
  double x, y, r;
  int object;  // index into Scene::objects
};

/// An object on the table before placement: its footprint radius and height, and a builder
/// that makes it at (x, y).
struct Candidate {
  std::string model;
  double footprint = 0.05;
  double height = 0.1;
};

struct Placer {
  double x_half = 0.3, y_half = 0.2;  // current region
  double x_max = 0.45, y_max = 0.3;   // fallback region
  double gap = 0.02;
  Vec3 look_at;
  double cam_radius = 1.0, cam_height = 1.0;  // the orbit's horizontal radius and height
  Vec3 camera = Vec3::Zero();  // the first frame's camera position
  std::vector<Footprint> taken;
  // objects that later objects must not hide from the first camera (the first mug): a
  // footprint and a height
  struct Protected {
    double x, y, r, height;
  };
  std::vector<Protected> keep_visible;

  bool free(double x, double y, double r, double height, int ignore = -1) const {
    for (const auto& f : taken) {
      if (f.object == ignore) continue;
      if (std::hypot(x - f.x, y - f.y) < r + f.r + gap) return false;
    }
    // keep away from the camera's orbit (the camera is never inside or just above an object)
    const double hd = std::hypot(x - look_at.x(), y - look_at.y());
    if (hd + r > cam_radius - 0.1 && height > cam_height - 0.1) return false;
    // do not hide a protected object's mid height from the first camera
    for (const auto& p : keep_visible) {
      const double sx = camera.x() - p.x, sy = camera.y() - p.y;
      const double len2 = sx * sx + sy * sy;
      if (len2 <= 0) continue;
      const double s = std::clamp(((x - p.x) * sx + (y - p.y) * sy) / len2, 0.0, 1.0);
      const double dist = std::hypot(x - (p.x + s * sx), y - (p.y + s * sy));
      const double sight = 0.5 * p.height + s * (camera.z() - 0.5 * p.height);
      if (dist < r + p.r && height > sight) return false;
    }
    return true;
  }

  bool place(Rng& rng, double r, double height, double& x, double& y) const {
    for (int attempt = 0; attempt < 240; ++attempt) {
      const double xh = attempt < 120 ? x_half : x_max;
      const double yh = attempt < 120 ? y_half : y_max;
      if (r > xh || r > yh) continue;
      x = rng.uniform(-xh + r, xh - r);
      y = rng.uniform(-yh + r, yh - r);
      if (free(x, y, r, height)) return true;
    }
    return false;
  }
};

enum class Model { Mug, Jar, Can, Bottle, Plate, Bowl, Box, TaperedCup };

Model random_model(Rng& rng) {
  const double u = rng.uniform();
  if (u < 0.20) return Model::Mug;
  if (u < 0.36) return Model::Jar;
  if (u < 0.46) return Model::Can;
  if (u < 0.61) return Model::Bottle;
  if (u < 0.71) return Model::Plate;
  if (u < 0.81) return Model::Bowl;
  return Model::Box;
}

Vec3 horizontal(double angle) { return Vec3(std::cos(angle), std::sin(angle), 0.0); }

/// A mug's handle other than a torus arc (handle_shapes "varied"): D-shaped ("d": large corners),
/// "squared" (corners just wider than the tube) or a flat "band", in the plane of the torus it
/// replaces (the body's axis and the direction u away from it), as far out from the wall as
/// that torus (`reach`, its centre line) and about as high (`span`, at most `max_span`), with
/// the tube radius `minor`. Its own sizes are drawn from `hr`, not from the scene's stream.
Shape varied_handle(const std::string& kind, Rng& hr, const Vec3& axis_point, double R, const Vec3& u,
                    double reach, double span, double max_span, double minor) {
  span = std::min(max_span, span * hr.uniform(0.95, 1.25));
  constexpr double kInset = 0.003;  // into the wall: no gap where a wide band meets the curved wall
  Shape s;
  s.cls = kind == "band" ? "band" : "loop";
  const double limit = std::min(reach, 0.5 * span);
  if (kind == "d") {
    s.minor_radius = minor;
    s.radius = std::clamp(hr.uniform(0.35, 0.6) * limit, 1.2 * minor, limit);
  } else if (kind == "squared") {
    s.minor_radius = minor;
    s.radius = std::min(minor * hr.uniform(1.1, 1.35), limit);
  } else {  // a band 2.4-4 mm thick, 12-20 mm wide
    s.minor_radius = hr.uniform(0.0012, 0.002);
    s.height = hr.uniform(0.012, 0.02);
    s.radius = std::clamp(hr.uniform(0.45, 0.9) * limit, 1.5 * s.minor_radius, limit);
  }
  const double x_in = R - s.radius - kInset, x_out = R + reach;  // from the body's axis
  s.point = axis_point + 0.5 * (x_in + x_out) * u;
  s.axis = u.cross(Vec3::UnitZ()).normalized();
  s.axis2 = u;
  s.size = Vec3(x_out - x_in, span, 0.0);
  return s;
}

/// Adds one object of `model` on the table; false if no place was found. `handle_rng`: draw
/// varied handles for mugs from it (handle_shapes "varied"); null: torus arcs.
bool add_object(Scene& scene, Placer& placer, Rng& rng, Model model, bool first_mug,
                Rng* handle_rng = nullptr) {
  SceneObject obj;
  obj.color = random_color(rng);
  const int index = int(scene.objects.size());
  double x = 0, y = 0;
  switch (model) {
    case Model::Mug: {
      const double R = rng.uniform(0.035, 0.05), h = rng.uniform(0.08, 0.11);
      const double wall = rng.uniform(0.003, 0.005), tb = rng.uniform(0.006, 0.012);
      const double minor = rng.uniform(0.004, 0.008);
      const double a = rng.uniform(0.02, std::min(0.03, 0.5 * h - minor - 0.004));
      const double kmax = std::min(0.8, 1.0 - (minor + 0.002) / a);
      const double k = rng.uniform(0.5, kmax);
      const double d = R + k * a;  // torus centre to body axis
      const double room = std::max(0.0, std::min(0.005, 0.5 * h - 0.003 - a - minor));
      const double zc = 0.5 * h + rng.uniform(-room, room);
      const double fr = d + a + minor;
      if (!placer.place(rng, fr, h, x, y)) return false;
      double phi = rng.uniform(0.0, 2 * kPi);
      if (first_mug) {
        // the first mug shows its handle from the side to the first camera
        const double az = scene.camera_azimuth_deg * kPi / 180.0;
        const Vec3 cam = scene.look_at + Vec3(std::cos(az), std::sin(az), 0.0);
        const double to_cam = std::atan2(cam.y() - y, cam.x() - x);
        const double side = rng.chance(0.5) ? 1.0 : -1.0;
        phi = to_cam + side * rng.uniform(50.0, 130.0) * kPi / 180.0;
      }
      const Vec3 u(std::cos(phi), std::sin(phi), 0.0);
      obj.model = "mug";
      obj.parts.emplace_back("body", cylinder(x, y, 0.0, h, R));
      obj.parts.emplace_back("inside", cylinder(x, y, tb, h, R - wall, true));
      obj.parts.emplace_back("rim", disc(x, y, h, R, R - wall));
      obj.parts.emplace_back("bottom", disc(x, y, tb, R - wall));
      Shape t;
      t.cls = "torus";
      t.point = Vec3(x, y, zc) + d * u;
      t.axis = u.cross(Vec3::UnitZ()).normalized();
      t.axis2 = u;
      t.radius = a;
      t.minor_radius = minor;
      const double half = std::acos(std::clamp(-k, -1.0, 1.0));
      t.arc_start = -half;
      t.arc_end = half;
      std::string kind = "torus";
      if (handle_rng != nullptr) {
        const double pick = handle_rng->uniform();
        kind = pick < 0.25 ? "torus" : pick < 0.5 ? "d" : pick < 0.75 ? "squared" : "band";
        obj.kind = kind;
      }
      if (kind == "torus") {
        obj.parts.emplace_back("handle", t);
      } else {
        const double max_span = 2 * std::min(h - 0.003 - minor - zc, zc - 0.003 - minor);
        obj.parts.emplace_back("handle", varied_handle(kind, *handle_rng, Vec3(x, y, zc), R, u, (k + 1) * a,
                                                       2 * a, max_span, minor));
      }
      placer.taken.push_back({x, y, fr, index});
      if (first_mug) placer.keep_visible.push_back({x, y, fr, h});
      break;
    }
    case Model::TaperedCup: {
      const double r0 = rng.uniform(0.022, 0.032), h = rng.uniform(0.07, 0.11);
      const double r1 = r0 + h * std::tan(rng.uniform(4.0, 10.0) * kPi / 180.0);
      const double wall = rng.uniform(0.003, 0.004), tb = rng.uniform(0.006, 0.01);
      if (!placer.place(rng, r1, h, x, y)) return false;
      obj.model = "tapered_cup";  // the concept of graphs/models/tabletop.yaml
      obj.parts.emplace_back("body", cone(x, y, 0.0, h, r0, r1));
      const double inner0 = r0 + (r1 - r0) * tb / h - wall;
      obj.parts.emplace_back("inside", cone(x, y, tb, h, inner0, r1 - wall, true));
      obj.parts.emplace_back("rim", disc(x, y, h, r1, r1 - wall));
      obj.parts.emplace_back("bottom", disc(x, y, tb, inner0));
      placer.taken.push_back({x, y, r1, index});
      break;
    }
    case Model::Jar:
    case Model::Can: {
      const bool jar = model == Model::Jar;
      const double R = jar ? rng.uniform(0.035, 0.06) : rng.uniform(0.032, 0.035);
      const double h = jar ? rng.uniform(0.08, 0.16) : rng.uniform(0.10, 0.12);
      if (!placer.place(rng, R, h, x, y)) return false;
      obj.model = jar ? "jar" : "can";
      obj.pose = "upright";
      obj.parts.emplace_back("body", cylinder(x, y, 0.0, h, R));
      obj.parts.emplace_back("lid", disc(x, y, h, R));
      obj.parts.emplace_back("base", disc(x, y, 0.0, R, 0.0, true));
      placer.taken.push_back({x, y, R, index});
      break;
    }
    case Model::Bottle: {
      const double rb = rng.uniform(0.03, 0.045), hb = rng.uniform(0.15, 0.22);
      const double rn = rng.uniform(0.01, 0.015), hn = rng.uniform(0.04, 0.06);
      if (!placer.place(rng, rb, hb + hn, x, y)) return false;
      obj.model = "bottle";
      obj.parts.emplace_back("body", cylinder(x, y, 0.0, hb, rb));
      obj.parts.emplace_back("shoulder", disc(x, y, hb, rb, rn));
      obj.parts.emplace_back("neck", cylinder(x, y, hb, hb + hn, rn));
      obj.parts.emplace_back("cap", disc(x, y, hb + hn, rn));
      placer.taken.push_back({x, y, rb, index});
      break;
    }
    case Model::Plate: {
      const double R = rng.uniform(0.09, 0.13), h = rng.uniform(0.015, 0.025);
      if (!placer.place(rng, R, h, x, y)) return false;
      obj.model = "plate";
      obj.parts.emplace_back("body", cylinder(x, y, 0.0, h, R));
      obj.parts.emplace_back("top", disc(x, y, h, R));
      placer.taken.push_back({x, y, R, index});
      break;
    }
    case Model::Bowl: {
      const double Ro = rng.uniform(0.06, 0.10), th = rng.uniform(0.004, 0.006);
      const double Ri = Ro - th;
      const double hmin = -(Ri + 0.002);  // flat foot on the table, 2 mm bottom
      const double hmax = -rng.uniform(0.0, 0.25) * Ro;
      const double zc = -hmin;
      if (!placer.place(rng, Ro, zc + hmax, x, y)) return false;
      obj.model = "bowl";
      Shape outer;
      outer.cls = "sphere";
      outer.point = Vec3(x, y, zc);
      outer.axis = Vec3::UnitZ();
      outer.radius = Ro;
      outer.height_min = hmin;
      outer.height_max = hmax;
      Shape inner = outer;
      inner.radius = Ri;
      inner.height_min = -Ri;
      inner.inward = true;
      obj.parts.emplace_back("body", outer);
      obj.parts.emplace_back("inside", inner);
      obj.parts.emplace_back("rim", disc(x, y, zc + hmax, std::sqrt(Ro * Ro - hmax * hmax),
                                         std::sqrt(Ri * Ri - hmax * hmax)));
      placer.taken.push_back({x, y, Ro, index});
      break;
    }
    case Model::Box: {
      const Vec3 size(rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2));
      const double yaw = rng.uniform(0.0, kPi);
      const double fr = 0.5 * std::hypot(size.x(), size.y());
      if (!placer.place(rng, fr, size.z(), x, y)) return false;
      obj.model = "box";
      obj.parts.emplace_back("box", box(Vec3(x, y, 0.5 * size.z()), yaw, size));
      placer.taken.push_back({x, y, fr, index});
      break;
    }
  }
  scene.objects.push_back(std::move(obj));
  return true;
}

/// A handle-like torus beside jar `jar_index`; false if no room. Plain: a half ring standing on
/// the table 1-2.5 cm from the jar, its plane through the jar's axis. Ambiguous: a full ring
/// leaning on the jar at its mid-height, its plane turned 35-70 degrees from the radial plane.
bool add_distractor(Scene& scene, Placer& placer, Rng& rng, int jar_index, bool ambiguous) {
  const Shape& body = scene.objects[jar_index].parts.front().second;
  const double Rj = body.radius;
  const double jx = body.point.x(), jy = body.point.y();
  const double a = rng.uniform(0.02, 0.03), minor = rng.uniform(0.004, 0.008);
  for (int attempt = 0; attempt < 40; ++attempt) {
    const double gap = ambiguous ? 0.0 : rng.uniform(0.01, 0.025);  // (drawn first: scenes stay as they were)
    const double phi = rng.uniform(0.0, 2 * kPi);
    const Vec3 u(std::cos(phi), std::sin(phi), 0.0);
    Vec3 e = u;  // the ring's horizontal in-plane direction: angle 0 points away from the jar
    double D = 0.0;  // its centre's distance to the jar's axis
    if (ambiguous) {
      const double beta = rng.uniform(35.0, 70.0) * kPi / 180.0;
      e = std::cos(beta) * u + std::sin(beta) * Vec3::UnitZ().cross(u);
      const double reach = Rj + rng.uniform(0.0, 0.003) + minor;  // its nearest point's distance to the axis
      D = a * std::cos(beta) + std::sqrt(std::max(0.0, reach * reach - std::pow(a * std::sin(beta), 2)));
    } else {
      D = Rj + gap + minor + a;
    }
    const double x = jx + D * u.x(), y = jy + D * u.y();
    const double fr = a + minor;
    if (std::abs(x) > placer.x_max - fr || std::abs(y) > placer.y_max - fr) continue;
    if (!placer.free(x, y, fr, fr, jar_index)) continue;
    SceneObject obj;
    obj.model = "distractor";
    obj.color = random_color(rng);
    Shape t;
    t.cls = "torus";
    t.point = Vec3(x, y, ambiguous ? body.point.z() : 0.0);
    t.axis = e.cross(Vec3::UnitZ()).normalized();
    t.axis2 = e;  // angle pi towards the jar, pi/2 is up
    t.radius = a;
    t.minor_radius = minor;
    t.arc_start = 0.0;
    t.arc_end = ambiguous ? 2 * kPi : kPi;
    obj.parts.emplace_back("handle", t);
    placer.taken.push_back({x, y, fr, int(scene.objects.size())});
    scene.objects.push_back(std::move(obj));
    return true;
  }
  return false;
}

/// A can or a jar lying on its side: its axis horizontal, resting on the table.
bool add_lying_container(Scene& scene, Placer& placer, Rng& rng) {
  const bool jar = rng.chance(0.5);
  const double R = jar ? rng.uniform(0.035, 0.06) : rng.uniform(0.032, 0.035);
  const double h = jar ? rng.uniform(0.08, 0.16) : rng.uniform(0.10, 0.12);
  const Vec3 a = horizontal(rng.uniform(0.0, kPi));
  const double fr = std::hypot(0.5 * h, R);
  double x = 0, y = 0;
  if (!placer.place(rng, fr, 2 * R, x, y)) return false;
  SceneObject obj;
  obj.model = jar ? "jar" : "can";
  obj.pose = "lying";
  obj.color = random_color(rng);
  Shape body;
  body.cls = "cylinder";
  body.point = Vec3(x, y, R);
  body.axis = a;
  body.radius = R;
  body.height = h;
  obj.parts.emplace_back("body", body);
  Shape lid = disc(0, 0, 0, R), base = disc(0, 0, 0, R);
  lid.point = body.point + 0.5 * h * a, lid.axis = a;
  base.point = body.point - 0.5 * h * a, base.axis = -a;
  obj.parts.emplace_back("lid", lid);
  obj.parts.emplace_back("base", base);
  placer.taken.push_back({x, y, fr, int(scene.objects.size())});
  scene.objects.push_back(std::move(obj));
  return true;
}



/// The lowest point's height of an ellipsoid or a box (full extents `size` along R's columns).
double lowest(const Vec3& centre, const Eigen::Matrix3d& R, const Vec3& size, bool ellipsoid) {
  double reach = 0;
  for (int i = 0; i < 3; ++i) {
    const double h = 0.5 * size[i] * R(2, i);
    reach += ellipsoid ? h * h : std::abs(h);
  }
  return centre.z() - (ellipsoid ? std::sqrt(reach) : reach);
}

/// Builds a free-form distractor of `kind` about the origin (resting on z = 0), its footprint
/// radius about the origin in `footprint`.
SceneObject freeform(int kind, Rng& rng, double& footprint) {
  SceneObject obj;
  obj.model = "other";
  obj.color = random_color(rng);
  footprint = 0;
  switch (kind) {
    case 0: {  // a blob: a main ellipsoid and one to three lobes that overlap it
      obj.kind = "blob";
      const Vec3 main(rng.uniform(0.06, 0.12), rng.uniform(0.05, 0.1), rng.uniform(0.04, 0.08));
      std::vector<std::pair<Vec3, Eigen::Matrix3d>> pose = {{Vec3::Zero(), rotation(rng.uniform(0.0, kPi), 0, 0)}};
      std::vector<Vec3> sizes = {main};
      const int lobes = rng.integer(1, 3);
      for (int i = 0; i < lobes; ++i) {
        const Vec3 size = main.cwiseProduct(Vec3(rng.uniform(0.5, 0.9), rng.uniform(0.5, 0.9), rng.uniform(0.5, 0.9)));
        const double az = rng.uniform(0.0, 2 * kPi), el = rng.uniform(-0.3, 0.8);
        const Vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        pose.emplace_back(0.35 * main.cwiseProduct(dir),
                          rotation(rng.uniform(0.0, 2 * kPi), rng.uniform(-0.7, 0.7), rng.uniform(-0.7, 0.7)));
        sizes.push_back(size);
      }
      double bottom = 1e9;
      for (std::size_t i = 0; i < sizes.size(); ++i) bottom = std::min(bottom, lowest(pose[i].first, pose[i].second, sizes[i], true));
      for (std::size_t i = 0; i < sizes.size(); ++i) {
        const Vec3 c = pose[i].first - bottom * Vec3::UnitZ();
        obj.parts.emplace_back("lobe" + std::to_string(i + 1), oriented("ellipsoid", c, pose[i].second, sizes[i]));
        footprint = std::max(footprint, c.head<2>().norm() + 0.5 * sizes[i].maxCoeff());
      }
      break;
    }
    case 1: {  // a banana: a bent tube (a torus arc) lying on its side, round tips, a stem
      obj.kind = "banana";
      obj.color = Eigen::Vector3f(float(rng.uniform(0.85, 0.95)), float(rng.uniform(0.7, 0.85)),
                                  float(rng.uniform(0.1, 0.3)));
      const double A = rng.uniform(0.07, 0.11), r = rng.uniform(0.016, 0.022);
      const double half = 0.5 * rng.uniform(60.0, 100.0) * kPi / 180.0;
      const double phi = rng.uniform(0.0, 2 * kPi);
      // the ring's centre, so that the middle of the footprint (between the arc's middle and
      // its chord) is at the origin
      const Vec3 c = -0.5 * A * (1 + std::cos(half)) * horizontal(phi) + r * Vec3::UnitZ();
      Shape tube;
      tube.cls = "torus";
      tube.point = c;
      tube.axis = Vec3::UnitZ();
      tube.axis2 = horizontal(phi);
      tube.radius = A;
      tube.minor_radius = r;
      tube.arc_start = -half;
      tube.arc_end = half;
      obj.parts.emplace_back("tube", tube);
      Shape tip;
      tip.cls = "sphere";
      tip.radius = r;
      tip.height_min = -r;
      tip.height_max = r;
      for (const double side : {-1.0, 1.0}) {
        tip.point = c + A * horizontal(phi + side * half);
        obj.parts.emplace_back(side < 0 ? "tip1" : "tip2", tip);
      }
      // the stem: a thin cylinder from the second tip along the tube's tangent, a little up
      const double len = rng.uniform(0.02, 0.03), rs = 0.35 * r;
      const Vec3 dir = (horizontal(phi + half + 0.5 * kPi) + 0.35 * Vec3::UnitZ()).normalized();
      Shape stem;
      stem.cls = "cylinder";
      stem.axis = dir;
      stem.radius = rs;
      stem.height = len + 0.5 * r;
      stem.point = c + A * horizontal(phi + half) + 0.5 * (len + 0.5 * r) * dir;
      obj.parts.emplace_back("stem", stem);
      Shape end = disc(0, 0, 0, rs);
      end.point = stem.point + 0.5 * stem.height * dir;
      end.axis = dir;
      obj.parts.emplace_back("stem_end", end);
      footprint = std::max(0.5 * A * (1 - std::cos(half)), A * std::sin(half)) + r + len;
      break;
    }
    case 2: {  // a drill: battery on the table, a grip leaning back, housing, chuck and bit
      obj.kind = "drill";
      if (rng.chance(0.6)) {  // black or dark grey plastic
        const float g = float(rng.uniform(0.06, 0.16));
        obj.color = Eigen::Vector3f(g, g, g * 1.05f);
      }
      const double yaw = rng.uniform(0.0, 2 * kPi);
      const Vec3 f = horizontal(yaw), z = Vec3::UnitZ();
      const Eigen::Matrix3d upright = rotation(yaw, 0, 0);
      const Vec3 battery(rng.uniform(0.09, 0.11), rng.uniform(0.07, 0.08), rng.uniform(0.05, 0.06));
      const Vec3 grip(rng.uniform(0.04, 0.05), rng.uniform(0.03, 0.035), rng.uniform(0.11, 0.13));
      const Vec3 housing(rng.uniform(0.13, 0.17), rng.uniform(0.06, 0.07), rng.uniform(0.065, 0.08));
      const double tilt = rng.uniform(10.0, 20.0) * kPi / 180.0;
      const double chuck_r = rng.uniform(0.014, 0.019), chuck_len = rng.uniform(0.03, 0.04);
      const double bit_r = rng.uniform(0.003, 0.005), bit_len = rng.uniform(0.03, 0.05);
      const double back = -0.25 * battery.x();  // along f: where the grip stands on the battery
      obj.parts.emplace_back("battery", oriented("box", Vec3(0, 0, 0.5 * battery.z()), upright, battery));
      // the grip's axis leans back (its top behind its foot); 1 cm into battery and housing
      const Vec3 g = std::cos(tilt) * z - std::sin(tilt) * f;
      const Vec3 foot = back * f + battery.z() * z;
      const Eigen::Matrix3d grip_frame = rotation(yaw, -tilt, 0);  // local z = g, local x = f turned up
      obj.parts.emplace_back("grip", oriented("box", foot + 0.5 * grip.z() * g, grip_frame,
                                              Vec3(grip.x(), grip.y(), grip.z() + 0.02)));
      const Vec3 top = foot + grip.z() * g;
      const Vec3 hc = top + (0.5 * housing.x() - 0.035) * f + (0.5 * housing.z() - 0.01) * z;
      obj.parts.emplace_back("housing", oriented("box", hc, upright, housing));
      Shape chuck;
      chuck.cls = "cylinder";
      chuck.axis = f;
      chuck.radius = chuck_r;
      chuck.height = chuck_len;
      chuck.point = hc + (0.5 * housing.x() + 0.5 * chuck_len) * f;
      obj.parts.emplace_back("chuck", chuck);
      Shape front = disc(0, 0, 0, chuck_r);
      front.point = chuck.point + 0.5 * chuck_len * f;
      front.axis = f;
      obj.parts.emplace_back("chuck_front", front);
      Shape bit = chuck;
      bit.radius = bit_r;
      bit.height = bit_len;
      bit.point = front.point + 0.5 * bit_len * f;
      obj.parts.emplace_back("bit", bit);
      Shape bit_end = disc(0, 0, 0, bit_r);
      bit_end.point = bit.point + 0.5 * bit_len * f;
      bit_end.axis = f;
      obj.parts.emplace_back("bit_end", bit_end);
      // centre the footprint along f between the battery's back and the bit's end
      const double rear = std::min(-0.5 * battery.x(), (hc - 0.5 * housing.x() * f).dot(f));
      const double ahead = bit_end.point.dot(f);
      const Vec3 shift = -0.5 * (rear + ahead) * f;
      for (auto& [role, sh] : obj.parts) sh.point += shift;
      footprint = std::hypot(0.5 * (ahead - rear), 0.5 * std::max(battery.y(), housing.y()));
      break;
    }
    default: {  // a rounded box (a soap, a phone, a case)
      obj.kind = "rounded_box";
      const Vec3 size(rng.uniform(0.06, 0.16), rng.uniform(0.05, 0.12), rng.uniform(0.03, 0.1));
      Shape b = oriented("rounded_box", Vec3(0, 0, 0.5 * size.z()), rotation(rng.uniform(0.0, kPi), 0, 0), size);
      b.radius = rng.uniform(0.15, 0.4) * size.minCoeff();
      obj.parts.emplace_back("box", b);
      footprint = 0.5 * std::hypot(size.x(), size.y());
      break;
    }
  }
  return obj;
}

/// Adds a free-form distractor of `kind` (0 blob, 1 banana, 2 drill, 3 rounded box): a few
/// tries with new sizes when the table is crowded.
bool add_freeform(Scene& scene, Placer& placer, Rng& rng, int kind) {
  for (int tries = 0; tries < 3; ++tries) {
    double fr = 0;
    SceneObject obj = freeform(kind, rng, fr);
    double top = 0;
    for (const auto& [role, sh] : obj.parts) top = std::max(top, sh.point.z() + 0.5 * sh.size.maxCoeff() + sh.radius);
    double x = 0, y = 0;
    if (!placer.place(rng, fr, top, x, y)) continue;
    for (auto& [role, sh] : obj.parts) sh.point += Vec3(x, y, 0.0);
    placer.taken.push_back({x, y, fr, int(scene.objects.size())});
    scene.objects.push_back(std::move(obj));
    return true;
  }
  return false;
}

void check_options(const SceneOptions& o) {
  if (o.width <= 0 || o.height <= 0 || o.width > 8192 || o.height > 8192)
    throw InputError("synthetic: image size must be 1 to 8192 pixels each way (width " + std::to_string(o.width) +
                     ", height " + std::to_string(o.height) + ")");
  if (const std::string p = o.intrinsics.problem(o.width, o.height); !p.empty())
    throw InputError("synthetic: intrinsics: " + p);
  if (o.min_objects < 0 || o.max_objects < o.min_objects)
    throw InputError("synthetic: need 0 <= min_objects <= max_objects (got " +
                     std::to_string(o.min_objects) + ", " + std::to_string(o.max_objects) + ")");
  if (!(o.min_distance > 0) || o.max_distance < o.min_distance)
    throw InputError("synthetic: need 0 < min_distance <= max_distance");
  if (o.min_elevation_deg < 0 || o.max_elevation_deg > 89.0 ||
      o.max_elevation_deg < o.min_elevation_deg)
    throw InputError("synthetic: need 0 <= min_elevation_deg <= max_elevation_deg <= 89");
  const StereoModel& s = o.stereo;
  if (!(s.baseline > 0) || !(s.noise_patch >= 1) || !(s.subpixel >= 1) || s.patch_noise_px < 0 ||
      s.pixel_noise_px < 0 || s.fattening_px < 0 || s.thin_px < 0 || !(s.max_range > s.min_range))
    throw InputError("synthetic: stereo model: need baseline > 0, noise_patch >= 1, subpixel >= 1, "
                     "noise, fattening and thin widths >= 0, max_range > min_range");
}

}  // namespace

Scene generate_scene(std::uint64_t seed, const SceneOptions& options) {
  check_options(options);
  if (options.room) return generate_room(seed, options);
  Rng rng(seed);
  Scene scene;
  scene.seed = seed;

  // table
  const double L = rng.uniform(1.0, 1.6), W = rng.uniform(0.7, 1.0), H = rng.uniform(0.7, 0.8);
  const double top = rng.uniform(0.025, 0.04), leg = rng.uniform(0.04, 0.06);
  const double inset = rng.uniform(0.03, 0.08);

  // camera of the first frame
  scene.look_at = Vec3(rng.uniform(-0.08, 0.08), rng.uniform(-0.05, 0.05), 0.0);
  scene.camera_distance = rng.uniform(options.min_distance, options.max_distance);
  scene.camera_elevation_deg = rng.uniform(options.min_elevation_deg, options.max_elevation_deg);
  scene.camera_azimuth_deg = rng.uniform(0.0, 360.0);

  // floor, wall (behind the table, opposite the first camera, beyond any orbit), table
  const double az = scene.camera_azimuth_deg * kPi / 180.0;
  const Vec3 away(-std::cos(az), -std::sin(az), 0.0);
  const double wall_distance =
      std::max(rng.uniform(2.5, 3.0), scene.camera_distance + 1.0);
  {
    SceneObject floor;
    floor.model = "floor";
    const double g = rng.uniform(0.3, 0.5);
    floor.color = Eigen::Vector3f(float(g), float(g * rng.uniform(0.9, 1.05)),
                                  float(g * rng.uniform(0.85, 1.0)));
    floor.parts.emplace_back("plane", plane(Vec3(0, 0, -H), Vec3::UnitZ()));
    scene.objects.push_back(std::move(floor));

    SceneObject wall;
    wall.model = "wall";
    const double w = rng.uniform(0.7, 0.9);
    wall.color = Eigen::Vector3f(float(w), float(w * rng.uniform(0.93, 1.0)),
                                 float(w * rng.uniform(0.85, 1.0)));
    wall.parts.emplace_back("plane", plane(wall_distance * away - Vec3(0, 0, H), -away));
    scene.objects.push_back(std::move(wall));

    SceneObject table;
    table.model = "table";
    table.color = Eigen::Vector3f(float(rng.uniform(0.55, 0.75)), float(rng.uniform(0.35, 0.5)),
                                  float(rng.uniform(0.18, 0.3)));
    table.parts.emplace_back("top", box(Vec3(0, 0, -0.5 * top), 0.0, Vec3(L, W, top)));
    const double lx = 0.5 * L - inset - 0.5 * leg, ly = 0.5 * W - inset - 0.5 * leg;
    const double sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
    for (int i = 0; i < 4; ++i)
      table.parts.emplace_back("leg" + std::to_string(i + 1),
                               box(Vec3(sx[i] * lx, sy[i] * ly, -0.5 * (H + top)), 0.0,
                                   Vec3(leg, leg, H - top)));
    scene.objects.push_back(std::move(table));
  }

  // objects on the table top
  Placer placer;
  placer.x_max = 0.5 * L - 0.03;
  placer.y_max = 0.5 * W - 0.03;
  placer.x_max = std::min(placer.x_max, 0.45);
  placer.y_max = std::min(placer.y_max, 0.32);
  placer.x_half = std::min(placer.x_max, 0.30);
  placer.y_half = std::min(placer.y_max, 0.22);
  placer.look_at = scene.look_at;
  const double el = scene.camera_elevation_deg * kPi / 180.0;
  placer.cam_radius = scene.camera_distance * std::cos(el);
  placer.cam_height = scene.camera_distance * std::sin(el);
  placer.camera = orbit_pose(scene.look_at, scene.camera_distance, scene.camera_elevation_deg,
                             scene.camera_azimuth_deg)
                      .translation();

  const int n = rng.integer(options.min_objects, options.max_objects);
  bool have_mug = false;
  // varied handles draw from a stream of their own: the scene is otherwise the same
  Rng handle_rng(seed ^ 0x4A1D1E5ull);
  Rng* handles = options.handle_shapes == HandleShapes::Varied ? &handle_rng : nullptr;
  for (int i = 0; i < n; ++i) {
    Model m;
    if (i == 0) {
      m = rng.chance(0.8) ? Model::Mug : random_model(rng);
    } else if (i == 1) {
      const double u = rng.uniform();
      m = u < 0.4 ? Model::Jar : u < 0.6 ? Model::Can : random_model(rng);
    } else {
      m = random_model(rng);
    }
    // a few tries with new sizes (and finally a smaller kind) when the table is crowded
    bool ok = false;
    for (int tries = 0; tries < 3 && !ok; ++tries)
      ok = add_object(scene, placer, rng, tries < 2 ? m : Model::Can,
                      m == Model::Mug && !have_mug && tries < 2, handles);
    if (ok && scene.objects.back().model == "mug") have_mug = true;
  }

  if (options.tapered_cups) {
    const int cups = rng.integer(1, 2);
    for (int i = 0; i < cups; ++i) add_object(scene, placer, rng, Model::TaperedCup, false, handles);
  }

  if (options.distractors || options.ambiguous_distractors) {
    const std::size_t count = scene.objects.size();
    bool first = true;
    for (std::size_t i = 0; i < count; ++i) {
      if (scene.objects[i].model != "jar") continue;
      if (first || rng.chance(0.5)) add_distractor(scene, placer, rng, int(i), options.ambiguous_distractors);
      first = false;
    }
  }

  // the options that add objects after all others (the scene before them stays as it was)
  if (options.lying_containers) {
    const int count = rng.integer(1, 2);
    for (int i = 0; i < count; ++i) add_lying_container(scene, placer, rng);
  }
  if (options.freeform_distractors) {
    const int count = rng.integer(1, 3), first = rng.integer(0, 3);
    for (int i = 0; i < count; ++i) add_freeform(scene, placer, rng, (first + i) % 4);
  }
  return scene;
}

// ---- JSON ---------------------------------------------------------------------------------

namespace {

nlohmann::json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json shape_json(const Shape& s) {
  nlohmann::json j;
  // a class of the shape table: its own fields (mereo/shapes/*.cpp), as in the results
  if (const auto seg = s.segment()) shapes::fields_to_json(seg->fields(), j);
  // and what the renderer adds
  if (s.cls == "torus") {
    j["arc_reference"] = vec_json(s.axis2), j["arc_start"] = s.arc_start, j["arc_end"] = s.arc_end;
  } else if (s.cls == "disc") {
    j = {{"center", vec_json(s.point)}, {"normal", vec_json(s.axis)}, {"radius", s.radius},
         {"inner_radius", s.minor_radius}};
  } else if (s.cls == "sphere") {
    j["axis"] = vec_json(s.axis), j["height_min"] = s.height_min, j["height_max"] = s.height_max;
  } else if (s.cls == "box" || s.cls == "ellipsoid" || s.cls == "rounded_box") {
    j = {{"center", vec_json(s.point)}, {"axis", vec_json(s.axis)},
         {"axis2", vec_json(s.axis2)}, {"size", vec_json(s.size)}};
    if (s.cls == "rounded_box") j["radius"] = s.radius;
  } else if (s.cls == "loop" || s.cls == "band") {
    j = {{"center", vec_json(s.point)}, {"normal", vec_json(s.axis)}, {"axis2", vec_json(s.axis2)},
         {"size", {s.size.x(), s.size.y()}}, {"corner_radius", s.radius}};
    if (s.cls == "loop") j["minor_radius"] = s.minor_radius;
    else j["thickness"] = 2 * s.minor_radius, j["width"] = s.height;
  }
  return j;
}

}  // namespace

std::string truth_to_json(const SyntheticFrame& f) {
  using nlohmann::json;
  json j;
  j["frame"] = f.frame.id;
  j["source"] = f.frame.source;
  const Intrinsics& K = f.frame.intrinsics;
  j["intrinsics"] = {{"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy},
                     {"width", f.frame.depth.cols()}, {"height", f.frame.depth.rows()}};
  const Eigen::Matrix4d M = f.truth.camera_pose.matrix();
  json pose = json::array();
  for (int r = 0; r < 4; ++r) pose.push_back({M(r, 0), M(r, 1), M(r, 2), M(r, 3)});
  j["camera_pose"] = pose;
  json objects = json::array();
  for (const auto& o : f.truth.objects_truth) {
    json jo = {{"id", o.id}, {"model", o.model}, {"visible_pixels", o.visible_pixels}};
    if (!o.pose.empty()) jo["pose"] = o.pose;
    if (!o.kind.empty()) jo["kind"] = o.kind;
    if (o.unoccluded_pixels > 0) jo["unoccluded_pixels"] = o.unoccluded_pixels;
    if (o.visible_pixels > 0) jo["visible_box"] = {{"min", vec_json(o.visible_min)}, {"max", vec_json(o.visible_max)}};
    json parts = json::array();
    for (const auto& p : o.parts) {
      parts.push_back({{"role", p.role},
                       {"label", p.label},
                       {"visible_pixels", p.visible_pixels},
                       {"class", p.world.cls},
                       {"camera", shape_json(p.camera)},
                       {"world", shape_json(p.world)}});
      if (p.unoccluded_pixels > 0) parts.back()["unoccluded_pixels"] = p.unoccluded_pixels;
    }
    jo["parts"] = parts;
    objects.push_back(jo);
  }
  j["objects"] = objects;
  return j.dump();
}

}  // namespace mereo::synthetic
