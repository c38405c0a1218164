// Tests of the synthetic renderer's shapes beyond the shape table's: mug handles that are not
// torus arcs ("loop": D-shaped and squared, "band"), ellipsoids and rounded boxes (free-form
// distractors), and cans and jars lying on their side. The ray-cast ground truth is checked
// against independent geometry: signed distance functions, and sphere tracing of them.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mereo/synthetic/scene.hpp"

namespace {

using mereo::synthetic::GroundTruth;
using mereo::synthetic::HandleShapes;
using mereo::synthetic::ObjectTruth;
using mereo::synthetic::PartTruth;
using mereo::synthetic::Scene;
using mereo::synthetic::SceneObject;
using mereo::synthetic::SceneOptions;
using mereo::synthetic::Shape;
using mereo::synthetic::SyntheticFrame;
using V3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

V3 back_project(const mereo::Intrinsics& K, int u, int v, double z) {
  return V3((u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z);
}

/// The shape's local frame: x = axis2 made orthogonal to the axis, y = axis x x, z = axis.
void frame_of(const Shape& s, V3& x, V3& y, V3& z) {
  z = s.axis.normalized();
  x = (s.axis2 - s.axis2.dot(z) * z).normalized();
  y = z.cross(x);
}

/// Signed distance in a plane to a rounded rectangle's outline (half extents hx, hy, corner
/// radius rc): negative inside; its absolute value is the distance to the outline.
double rounded_rectangle(double px, double py, double hx, double hy, double rc) {
  const double qx = std::abs(px) - (hx - rc), qy = std::abs(py) - (hy - rc);
  return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0) - rc;
}

/// Signed distance (or, for the ellipsoid, a lower bound of it) to the solid of a shape:
/// "loop", "band", "rounded_box", "ellipsoid", and closed "cylinder".
double sdf(const Shape& s, const V3& p) {
  V3 x, y, z;
  frame_of(s, x, y, z);
  const V3 w = p - s.point;
  const V3 q(w.dot(x), w.dot(y), w.dot(z));
  if (s.cls == "loop" || s.cls == "band") {
    const double d = rounded_rectangle(q.x(), q.y(), 0.5 * s.size.x(), 0.5 * s.size.y(), s.radius);
    if (s.cls == "loop") return std::hypot(d, q.z()) - s.minor_radius;
    const double a = std::abs(d) - s.minor_radius, b = std::abs(q.z()) - 0.5 * s.height;
    return std::hypot(std::max(a, 0.0), std::max(b, 0.0)) + std::min(std::max(a, b), 0.0);
  }
  if (s.cls == "rounded_box") {
    const V3 e = q.cwiseAbs() - (0.5 * s.size - V3::Constant(s.radius));
    return e.cwiseMax(0.0).norm() + std::min(e.maxCoeff(), 0.0) - s.radius;
  }
  if (s.cls == "ellipsoid") {
    const V3 half = 0.5 * s.size;
    return (q.cwiseQuotient(half).norm() - 1.0) * half.minCoeff();
  }
  if (s.cls == "cylinder") {
    const double a = std::hypot(q.x(), q.y()) - s.radius, b = std::abs(q.z()) - 0.5 * s.height;
    return std::hypot(std::max(a, 0.0), std::max(b, 0.0)) + std::min(std::max(a, b), 0.0);
  }
  ADD_FAILURE() << "no distance function for " << s.cls;
  return 1e9;
}

V3 sdf_gradient(const Shape& s, const V3& p) {
  constexpr double h = 1e-6;
  V3 g;
  for (int i = 0; i < 3; ++i) {
    V3 a = p, b = p;
    a[i] += h, b[i] -= h;
    g[i] = (sdf(s, a) - sdf(s, b)) / (2 * h);
  }
  return g.normalized();
}

/// Distance to the ellipsoid's surface along the line from its centre through p (an upper
/// bound of the true distance: 0 exactly on the surface).
double ellipsoid_offset(const Shape& s, const V3& p) {
  V3 x, y, z;
  frame_of(s, x, y, z);
  const V3 w = p - s.point;
  const V3 q(w.dot(x) / (0.5 * s.size.x()), w.dot(y) / (0.5 * s.size.y()), w.dot(z) / (0.5 * s.size.z()));
  return w.norm() * std::abs(1.0 - 1.0 / q.norm());
}

double angle_deg(const V3& a, const V3& b) {
  return std::acos(std::clamp(std::abs(a.normalized().dot(b.normalized())), 0.0, 1.0)) * 180.0 / kPi;
}

SceneOptions all_new(bool noise = false) {
  SceneOptions o;
  o.noise = noise;
  o.handle_shapes = HandleShapes::Varied;
  o.lying_containers = true;
  o.freeform_distractors = true;
  return o;
}

/// Is p inside the closed cylinder of a mug's body?
bool inside_body(const Shape& body, const V3& p) {
  const V3 w = p - body.point;
  const double a = w.dot(body.axis.normalized());
  return std::abs(a) <= 0.5 * body.height && (w - a * body.axis.normalized()).norm() < body.radius;
}

}  // namespace

TEST(SyntheticShapes, CompositeShapesAgreeWithSphereTracing) {
  // Loops (D-shaped, squared), a band, a rounded box and an ellipsoid in front of the camera;
  // a mug whose loop handle goes into its body (closed here: lid and base). Every pixel's
  // ray-cast depth and object against sphere tracing of the signed distance functions.
  Scene scene;
  scene.seed = 1;
  auto add = [&](const std::string& model, std::vector<std::pair<std::string, Shape>> parts) {
    SceneObject o;
    o.model = model;
    o.parts = std::move(parts);
    scene.objects.push_back(o);
  };
  auto shape = [](const std::string& cls, V3 point, V3 axis, V3 axis2, V3 size, double radius, double minor,
                  double height = 0) {
    Shape s;
    s.cls = cls, s.point = point, s.axis = axis.normalized(), s.axis2 = axis2.normalized(), s.size = size;
    s.radius = radius, s.minor_radius = minor, s.height = height;
    return s;
  };
  add("a", {{"handle", shape("loop", V3(-0.12, -0.07, 0.55), V3(0.3, 0.2, -1), V3(1, 0.2, 0), V3(0.07, 0.06, 0), 0.02, 0.006)}});
  add("b", {{"handle", shape("loop", V3(0.0, -0.08, 0.6), V3(0, 0.6, -1), V3(1, 0, 0.3), V3(0.06, 0.07, 0), 0.007, 0.006)}});
  add("c", {{"handle", shape("band", V3(0.12, -0.07, 0.55), V3(-0.4, 0.1, -1), V3(0, 1, 0.2), V3(0.06, 0.07, 0), 0.02, 0.002, 0.018)}});
  add("d", {{"box", shape("rounded_box", V3(-0.12, 0.06, 0.6), V3(0.2, -1, -0.5), V3(1, 0.3, 0), V3(0.1, 0.06, 0.05), 0.015, 0)}});
  add("e", {{"lobe", shape("ellipsoid", V3(0.0, 0.07, 0.62), V3(0.5, -1, -0.2), V3(1, 0.4, 0), V3(0.08, 0.05, 0.035), 0, 0)}});
  // the mug: body axis up (-y in the camera), a D handle pointing right, into the wall
  const V3 up(0, -1, 0), out(1, 0, 0);
  Shape body = shape("cylinder", V3(0.1, 0.07, 0.65), up, out, V3::Zero(), 0.035, 0);
  body.height = 0.09;
  Shape lid = shape("disc", body.point + 0.045 * up, up, out, V3::Zero(), 0.035, 0);
  Shape base = shape("disc", body.point - 0.045 * up, -up, out, V3::Zero(), 0.035, 0);
  const double rc = 0.012, inset = 0.003, reach = 0.03;
  const double x_in = 0.035 - rc - inset, x_out = 0.035 + reach;
  Shape handle = shape("loop", body.point + 0.5 * (x_in + x_out) * out, V3(0, 0.25, -1).cross(out).cross(out).normalized(),
                       out, V3(x_out - x_in, 0.06, 0), rc, 0.005);
  handle.axis = out.cross(up).normalized();  // the handle's plane holds the body's axis
  add("mug", {{"body", body}, {"lid", lid}, {"base", base}, {"handle", handle}});

  SceneOptions o;
  o.noise = false;
  o.width = 480;
  o.height = 360;
  o.intrinsics = mereo::Intrinsics{393.75, 393.75, 239.5, 179.5};
  const SyntheticFrame f = mereo::synthetic::render(scene, mereo::Pose::Identity(), o);
  const GroundTruth& gt = f.truth;

  // each object's solid for the tracer (the mug's: its closed body and its handle)
  std::vector<std::pair<std::uint32_t, Shape>> solids;
  for (const auto& ot : gt.objects_truth)
    for (const auto& p : ot.parts)
      if (p.camera.cls != "disc") solids.emplace_back(ot.id, p.camera);

  std::size_t covered = 0, disagree = 0, disagree_inside = 0;
  double worst = 0;
  std::map<std::uint32_t, std::size_t> seen;
  for (int v = 0; v < o.height; ++v) {
    for (int u = 0; u < o.width; ++u) {
      const V3 d = V3((u - 239.5) / 393.75, (v - 179.5) / 393.75, 1.0).normalized();
      double t = 0.3;
      std::uint32_t hit = 0;
      for (int step = 0; step < 4000 && t < 2.0; ++step) {
        double best = 1e9;
        std::uint32_t id = 0;
        for (const auto& [oid, s] : solids) {
          const double dist = sdf(s, t * d);
          if (dist < best) best = dist, id = oid;
        }
        if (best < 1e-8) {
          hit = id;
          break;
        }
        t += best;
      }
      const std::uint32_t rendered = gt.objects(v, u);
      if (hit == 0 && rendered == 0) continue;
      ++covered;
      if (hit != rendered) {
        ++disagree;
        // only where the ray grazes a silhouette: a neighbour shows something else
        bool edge = false;
        for (int dv = -1; dv <= 1; ++dv)
          for (int du = -1; du <= 1; ++du) {
            const int uu = std::clamp(u + du, 0, o.width - 1), vv = std::clamp(v + dv, 0, o.height - 1);
            edge |= gt.objects(vv, uu) != rendered;
          }
        disagree_inside += !edge;
        continue;
      }
      ++seen[hit];
      worst = std::max(worst, std::abs(t * d.z() - gt.depth(v, u)));
    }
  }
  std::cout << "[ info     ] sphere tracing: " << covered << " pixels, " << disagree
            << " disagree (on silhouettes), depth within " << worst * 1e3 << " mm\n";
  EXPECT_EQ(seen.size(), 6u) << "every object is seen";
  for (const auto& [id, n] : seen) EXPECT_GT(n, 200u) << "object " << id;
  EXPECT_LT(worst, 0.0001);
  EXPECT_EQ(disagree_inside, 0u);
  EXPECT_LT(disagree, covered / 200);

  // the mug's handle is drawn only outside the body, and shows both of its arms
  const ObjectTruth& mug = gt.objects_truth.back();
  const PartTruth* h = mug.part("handle");
  const PartTruth* b = mug.part("body");
  ASSERT_GT(h->visible_pixels, 200u);
  for (int v = 0; v < o.height; ++v)
    for (int u = 0; u < o.width; ++u)
      if (gt.parts(v, u) == h->label)
        EXPECT_FALSE(inside_body(b->camera, back_project(o.intrinsics, u, v, gt.depth(v, u))));
}

TEST(SyntheticShapes, GeneratedScenesLieOnTheirSurfaces) {
  // Every pixel of a new shape in generated scenes (varied handles, lying cans and jars,
  // free-form distractors) lies on its part's analytic surface, with its normal
  std::map<std::string, std::size_t> pixels;  // per class
  std::set<std::string> handle_kinds, other_kinds;
  for (std::uint64_t seed = 1; seed <= 16; ++seed) {
    const SyntheticFrame f = mereo::synthetic::render(seed, all_new());
    const GroundTruth& gt = f.truth;
    const auto& K = f.frame.intrinsics;
    std::vector<const PartTruth*> part(1, nullptr);
    std::vector<const ObjectTruth*> object(1, nullptr);
    for (const auto& o : gt.objects_truth) {
      if (o.model == "mug") {
        ASSERT_NE(o.part("handle"), nullptr);
        handle_kinds.insert(o.kind);
        const std::string cls = o.part("handle")->world.cls;
        EXPECT_EQ(cls, o.kind == "torus" ? "torus" : o.kind == "band" ? "band" : "loop") << o.kind;
      }
      if (o.model == "other") other_kinds.insert(o.kind);
      for (const auto& p : o.parts) {
        part.resize(std::max<std::size_t>(part.size(), p.label + 1), nullptr);
        object.resize(part.size(), nullptr);
        part[p.label] = &p;
        object[p.label] = &o;
      }
    }
    for (int v = 0; v < gt.depth.rows(); ++v) {
      for (int u = 0; u < gt.depth.cols(); ++u) {
        const std::uint32_t label = gt.parts(v, u);
        if (label == 0) continue;
        const PartTruth& pt = *part.at(label);
        const ObjectTruth& ot = *object.at(label);
        EXPECT_EQ(gt.objects(v, u), ot.id);
        const Shape& s = pt.camera;
        const bool lying = ot.pose == "lying";
        if (s.cls != "loop" && s.cls != "band" && s.cls != "rounded_box" && s.cls != "ellipsoid" && !lying &&
            ot.model != "other")
          continue;  // the others: test_synthetic.cpp
        const V3 p = back_project(K, u, v, gt.depth(v, u));
        const float* np = gt.normals.ptr(v, u);
        const V3 n(np[0], np[1], np[2]);
        const double tol = 0.0003 + 1e-6 * p.z() * p.z();
        double dist = 0;
        V3 exact = n;
        if (s.cls == "ellipsoid") {
          dist = ellipsoid_offset(s, p);
          V3 x, y, z;
          frame_of(s, x, y, z);
          const V3 w = p - s.point, h2 = (0.5 * s.size).cwiseProduct(0.5 * s.size);
          exact = w.dot(x) / h2.x() * x + w.dot(y) / h2.y() * y + w.dot(z) / h2.z() * z;
        } else if (s.cls == "loop" || s.cls == "band" || s.cls == "rounded_box") {
          dist = sdf(s, p);
          if (s.cls != "band") exact = sdf_gradient(s, p);  // (a band's edges are sharp)
        } else if (s.cls == "cylinder") {
          const V3 a = s.axis.normalized(), w = p - s.point;
          dist = (w - w.dot(a) * a).norm() - s.radius;
          EXPECT_LE(std::abs(w.dot(a)), 0.5 * s.height + tol);
          exact = w - w.dot(a) * a;
        } else if (s.cls == "disc") {
          const V3 a = s.axis.normalized(), w = p - s.point;
          dist = w.dot(a);
          EXPECT_LE((w - w.dot(a) * a).norm(), s.radius + tol);
          exact = a;
        } else if (s.cls == "sphere") {
          dist = (p - s.point).norm() - s.radius;
          exact = p - s.point;
        } else if (s.cls == "torus") {
          const V3 a = s.axis.normalized(), w = p - s.point;
          const V3 ring = s.radius * (w - w.dot(a) * a).normalized();
          dist = (w - ring).norm() - s.minor_radius;
          exact = w - ring;
        } else if (s.cls == "box") {
          V3 x, y, z;
          frame_of(s, x, y, z);
          const V3 w = p - s.point;
          const V3 q(w.dot(x), w.dot(y), w.dot(z));
          dist = ((q.cwiseAbs() - 0.5 * s.size).maxCoeff());
          exact = n;
        } else {
          ADD_FAILURE() << "unexpected class " << s.cls;
        }
        EXPECT_LT(std::abs(dist), tol) << "seed " << seed << " " << ot.model << " " << ot.kind << " " << pt.role;
        // normals: away from sharp edges, where the numeric gradient is meaningful
        if (std::abs(dist) < tol) {
          EXPECT_LT(angle_deg(n, exact), 1.5) << "seed " << seed << " " << s.cls << " " << pt.role;
        }
        if (ot.model == "mug" && pt.role == "handle")
          EXPECT_FALSE(inside_body(ot.part("body")->camera, p)) << "seed " << seed;
        ++pixels[s.cls];
      }
    }
  }
  for (const auto& [cls, n] : pixels) std::cout << "[ info     ] " << n << " pixels of " << cls << " checked\n";
  for (const char* cls : {"loop", "band", "rounded_box", "ellipsoid", "torus", "sphere", "box", "cylinder"})
    EXPECT_GT(pixels[cls], 300u) << cls;
  EXPECT_EQ(handle_kinds, (std::set<std::string>{"torus", "d", "squared", "band"}));
  EXPECT_EQ(other_kinds, (std::set<std::string>{"blob", "banana", "drill", "rounded_box"}));
}

TEST(SyntheticShapes, VariedHandlesReplaceOnlyTheHandles) {
  // handle_shapes "varied": the same scene, the same mugs, their handles in the torus's plane,
  // as far out from the wall, and drawn as the mug's "handle" part
  SceneOptions varied;
  varied.handle_shapes = HandleShapes::Varied;
  std::map<std::string, int> kinds, seen;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const Scene a = mereo::synthetic::generate_scene(seed), b = mereo::synthetic::generate_scene(seed, varied);
    ASSERT_EQ(a.objects.size(), b.objects.size());
    for (std::size_t i = 0; i < a.objects.size(); ++i) {
      const SceneObject &x = a.objects[i], &y = b.objects[i];
      ASSERT_EQ(x.model, y.model);
      ASSERT_EQ(x.parts.size(), y.parts.size());
      for (std::size_t k = 0; k < x.parts.size(); ++k) {
        EXPECT_EQ(x.parts[k].first, y.parts[k].first);
        if (x.parts[k].first == "handle" && x.model == "mug") continue;
        EXPECT_EQ(x.parts[k].second.point, y.parts[k].second.point);
      }
      if (x.model != "mug") continue;
      EXPECT_EQ(x.kind, "");
      ++kinds[y.kind];
      const Shape& t = x.parts.back().second;
      const Shape& h = y.parts.back().second;
      const Shape& body = y.parts.front().second;
      if (y.kind == "torus") {
        EXPECT_EQ(h.point, t.point);
        continue;
      }
      // in the torus's plane, reaching as far from the body's axis
      EXPECT_NEAR(std::abs(h.axis.dot(t.axis)), 1.0, 1e-12);
      EXPECT_NEAR((h.point - body.point).dot(h.axis), 0.0, 1e-12);
      const double torus_reach = (t.point - body.point).head<2>().norm() + t.radius;
      const double reach = (h.point - body.point).head<2>().norm() + 0.5 * h.size.x();
      EXPECT_NEAR(reach, torus_reach, 1e-9);
      // within the body's height
      EXPECT_GE(h.point.z() - 0.5 * h.size.y() - (h.cls == "band" ? h.minor_radius : h.minor_radius), 0.0);
      EXPECT_LE(h.point.z() + 0.5 * h.size.y() + h.minor_radius, body.height);
      if (y.kind == "squared") EXPECT_LT(h.radius, 1.4 * h.minor_radius);
      if (y.kind == "d") EXPECT_GT(h.radius, 1.19 * h.minor_radius);
      if (y.kind == "band") {
        EXPECT_GE(h.height, 0.012);
        EXPECT_LE(2 * h.minor_radius, 0.004);
      }
    }
    // rendered: a handle part of the mug, model "mug"
    SceneOptions clean = varied;
    clean.noise = false;
    const SyntheticFrame f = mereo::synthetic::render(seed, clean);
    for (const auto& o : f.truth.objects_truth)
      if (o.model == "mug" && o.part("handle")->visible_pixels > 100) ++seen[o.kind];
  }
  for (const auto& [k, n] : kinds) std::cout << "[ info     ] " << n << " mugs with a " << k << " handle\n";
  for (const char* k : {"torus", "d", "squared", "band"}) {
    EXPECT_GE(kinds[k], 3) << k;
    EXPECT_GE(seen[k], 2) << k << " handles in view";
  }
}

TEST(SyntheticShapes, LyingContainersRestOnTheTable) {
  int lying = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SceneOptions o;
    o.lying_containers = true;
    const Scene s = mereo::synthetic::generate_scene(seed, o);
    const Scene before = mereo::synthetic::generate_scene(seed);
    ASSERT_GT(s.objects.size(), before.objects.size()) << "seed " << seed;
    for (std::size_t i = 0; i < before.objects.size(); ++i) EXPECT_EQ(s.objects[i].model, before.objects[i].model);
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const SceneObject& obj = s.objects[i];
      if (obj.model != "can" && obj.model != "jar") {
        EXPECT_EQ(obj.pose, "");
        continue;
      }
      EXPECT_EQ(obj.pose, i < before.objects.size() ? "upright" : "lying");
      if (obj.pose != "lying") continue;
      ++lying;
      const Shape& body = obj.parts.at(0).second;
      ASSERT_EQ(obj.parts.at(0).first, "body");
      EXPECT_EQ(body.cls, "cylinder");
      EXPECT_NEAR(body.axis.z(), 0.0, 1e-12);
      EXPECT_NEAR(body.point.z(), body.radius, 1e-12);  // resting on its side
      for (const auto& [role, part] : obj.parts) {
        if (role == "body") continue;
        EXPECT_EQ(part.cls, "disc");
        EXPECT_NEAR(std::abs((part.point - body.point).dot(body.axis)), 0.5 * body.height, 1e-12);
        EXPECT_NEAR(std::abs(part.axis.dot(body.axis)), 1.0, 1e-12);
      }
    }
  }
  EXPECT_GE(lying, 30);
  // the truth JSON says how it stands
  SceneOptions o = all_new();
  const auto j = nlohmann::json::parse(mereo::synthetic::truth_to_json(mereo::synthetic::render(3, o)));
  int poses = 0;
  for (const auto& obj : j["objects"]) {
    if (obj["model"] == "can" || obj["model"] == "jar") {
      ASSERT_TRUE(obj.contains("pose"));
      EXPECT_TRUE(obj["pose"] == "lying" || obj["pose"] == "upright");
      poses += obj["pose"] == "lying";
    } else {
      EXPECT_FALSE(obj.contains("pose"));
    }
  }
  EXPECT_GE(poses, 1);
}

TEST(SyntheticShapes, FreeformDistractorsAreOtherAndRestOnTheTable) {
  std::map<std::string, int> kinds;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SceneOptions o;
    o.freeform_distractors = true;
    const Scene s = mereo::synthetic::generate_scene(seed, o);
    const Scene before = mereo::synthetic::generate_scene(seed);
    for (std::size_t i = 0; i < before.objects.size(); ++i) {
      EXPECT_EQ(s.objects[i].model, before.objects[i].model);
      EXPECT_EQ(s.objects[i].parts.front().second.point, before.objects[i].parts.front().second.point);
    }
    for (std::size_t i = before.objects.size(); i < s.objects.size(); ++i) {
      const SceneObject& obj = s.objects[i];
      EXPECT_EQ(obj.model, "other");
      ++kinds[obj.kind];
      // its lowest point touches the table top: sample every part's surface
      double low = 1e9;
      for (const auto& [role, sh] : obj.parts) {
        EXPECT_NE(role, "body") << "an 'other' has no body (evaluate.py matches bodies)";
        V3 x, y, z;
        frame_of(sh, x, y, z);
        const V3 h = 0.5 * sh.size;
        for (int i = 0; i < 40; ++i)
          for (int k = 0; k <= 20; ++k) {
            const double az = 2 * kPi * i / 40, el = kPi * (k / 20.0 - 0.5);
            const V3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
            V3 p;
            if (sh.cls == "ellipsoid") {
              p = sh.point + h.x() * dir.x() * x + h.y() * dir.y() * y + h.z() * dir.z() * z;
            } else if (sh.cls == "sphere") {
              p = sh.point + sh.radius * dir;
            } else if (sh.cls == "box" || sh.cls == "rounded_box") {
              // a corner (a rounded box's: of its flat faces, as it lies with local z up)
              p = sh.point;
              for (int c = 0; c < 3; ++c) {
                const double e = sh.cls == "rounded_box" && c < 2 ? h[c] - sh.radius : h[c];
                p += (dir[c] < 0 ? -e : e) * (c == 0 ? x : c == 1 ? y : z);
              }
            } else if (sh.cls == "torus") {
              const double th = sh.arc_start + (sh.arc_end - sh.arc_start) * i / 39.0;
              const V3 r = std::cos(th) * x + std::sin(th) * y;
              p = sh.point + sh.radius * r + sh.minor_radius * (std::cos(el) * r + std::sin(el) * z);
            } else if (sh.cls == "cylinder") {
              const V3 a = sh.axis.normalized(), b = a.cross(V3::UnitZ()).normalized(), c = a.cross(b);
              p = sh.point + (k / 10.0 - 1) * 0.5 * sh.height * a + sh.radius * (std::cos(az) * b + std::sin(az) * c);
            } else {
              continue;  // discs close cylinders
            }
            low = std::min(low, p.z());
          }
      }
      EXPECT_NEAR(low, 0.0, 0.002) << obj.kind << " seed " << seed;
      EXPECT_GE(low, -1e-9) << obj.kind << " seed " << seed;
    }
  }
  for (const auto& [k, n] : kinds) std::cout << "[ info     ] " << n << " free-form distractors: " << k << "\n";
  for (const char* k : {"blob", "banana", "drill", "rounded_box"}) EXPECT_GE(kinds[k], 5) << k;
  // the truth JSON names them "other", with their kind
  const auto j = nlohmann::json::parse(mereo::synthetic::truth_to_json(mereo::synthetic::render(2, all_new())));
  int others = 0;
  for (const auto& obj : j["objects"])
    if (obj["model"] == "other") {
      ++others;
      EXPECT_TRUE(obj.contains("kind"));
      for (const auto& p : obj["parts"]) EXPECT_TRUE(p["camera"].is_object());
    }
  EXPECT_GE(others, 1);
}

TEST(SyntheticShapes, TruthJsonOfTheNewClasses) {
  bool loop = false, band = false, ellipsoid = false, rounded = false;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const SyntheticFrame f = mereo::synthetic::render(seed, all_new());
    const auto j = nlohmann::json::parse(mereo::synthetic::truth_to_json(f));
    for (const auto& obj : j["objects"])
      for (const auto& p : obj["parts"]) {
        const auto& c = p["camera"];
        if (p["class"] == "loop" || p["class"] == "band") {
          (p["class"] == "loop" ? loop : band) = true;
          for (const char* k : {"center", "normal", "axis2", "size", "corner_radius"}) EXPECT_TRUE(c.contains(k)) << k;
          EXPECT_TRUE(c.contains(p["class"] == "loop" ? "minor_radius" : "thickness"));
          EXPECT_EQ(obj["model"], "mug");
          EXPECT_EQ(p["role"], "handle");
        }
        if (p["class"] == "ellipsoid" || p["class"] == "rounded_box") {
          (p["class"] == "ellipsoid" ? ellipsoid : rounded) = true;
          for (const char* k : {"center", "axis", "axis2", "size"}) EXPECT_TRUE(c.contains(k)) << k;
        }
      }
  }
  EXPECT_TRUE(loop && band && ellipsoid && rounded);
}

TEST(SyntheticShapes, VisibleBoxesHoldTheVisiblePoints) {
  const SyntheticFrame f = mereo::synthetic::render(5, all_new());
  const GroundTruth& gt = f.truth;
  std::map<std::uint32_t, std::pair<V3, V3>> box;
  for (int v = 0; v < gt.depth.rows(); ++v)
    for (int u = 0; u < gt.depth.cols(); ++u) {
      const std::uint32_t id = gt.objects(v, u);
      if (id == 0) continue;
      const V3 p = back_project(f.frame.intrinsics, u, v, gt.depth(v, u));
      auto [it, fresh] = box.try_emplace(id, p, p);
      it->second.first = it->second.first.cwiseMin(p);
      it->second.second = it->second.second.cwiseMax(p);
    }
  const auto j = nlohmann::json::parse(mereo::synthetic::truth_to_json(f));
  for (std::size_t i = 0; i < gt.objects_truth.size(); ++i) {
    const ObjectTruth& o = gt.objects_truth[i];
    if (o.visible_pixels == 0) {
      EXPECT_FALSE(j["objects"][i].contains("visible_box"));
      continue;
    }
    const auto& [lo, hi] = box.at(o.id);
    for (int k = 0; k < 3; ++k) {  // (the depth image is float: its points within ~1e-7 z)
      EXPECT_NEAR(o.visible_min[k], lo[k], 1e-6 + 1e-6 * std::abs(lo[k])) << o.model;
      EXPECT_NEAR(o.visible_max[k], hi[k], 1e-6 + 1e-6 * std::abs(hi[k])) << o.model;
      EXPECT_DOUBLE_EQ(j["objects"][i]["visible_box"]["min"][k].get<double>(), o.visible_min[k]);
    }
  }
}
