// Tests of the synthetic RGB-D scene renderer against independent analytic geometry.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include "mereo/synthetic/scene.hpp"

namespace {

using mereo::synthetic::GroundTruth;
using mereo::synthetic::ObjectTruth;
using mereo::synthetic::PartTruth;
using mereo::synthetic::SceneOptions;
using mereo::synthetic::Shape;
using mereo::synthetic::SyntheticFrame;
using V3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
const std::vector<std::uint64_t> kSeeds = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};

V3 back_project(const mereo::Intrinsics& K, int u, int v, double z) {
  return V3((u - K.cx) * z / K.fx, (v - K.cy) * z / K.fy, z);
}

V3 normal_at(const GroundTruth& gt, int u, int v) {
  const float* n = gt.normals.ptr(v, u);
  return V3(n[0], n[1], n[2]);
}

/// Distance from p to the lateral surface of a cylinder, and its axial offset from the middle.
double cylinder_distance(const Shape& c, const V3& p, double& axial, V3& normal) {
  const V3 w = p - c.point;
  axial = w.dot(c.axis);
  const V3 radial = w - axial * c.axis;
  normal = radial.normalized();
  return radial.norm() - c.radius;
}

/// Distance from p to a torus surface (distance to the ring circle minus the minor radius).
double torus_distance(const Shape& t, const V3& p, V3& normal) {
  const V3 w = p - t.point;
  const V3 in_plane = w - w.dot(t.axis) * t.axis;
  const V3 ring = t.radius * in_plane.normalized();
  normal = (w - ring).normalized();
  return (w - ring).norm() - t.minor_radius;
}

double angle_deg(V3 a, const V3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

SceneOptions clean_options() {
  SceneOptions o;
  o.noise = false;
  return o;
}

}  // namespace

TEST(SyntheticScene, SameSeedSameScene) {
  const auto a = mereo::synthetic::generate_scene(42);
  const auto b = mereo::synthetic::generate_scene(42);
  const auto c = mereo::synthetic::generate_scene(43);
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].model, b.objects[i].model);
    ASSERT_EQ(a.objects[i].parts.size(), b.objects[i].parts.size());
    for (std::size_t k = 0; k < a.objects[i].parts.size(); ++k)
      EXPECT_EQ(a.objects[i].parts[k].second.point, b.objects[i].parts[k].second.point);
  }
  EXPECT_EQ(a.camera_distance, b.camera_distance);
  EXPECT_NE(a.camera_distance, c.camera_distance);
  EXPECT_EQ(a.objects[0].model, "floor");
  EXPECT_EQ(a.objects[1].model, "wall");
  EXPECT_EQ(a.objects[2].model, "table");
}

TEST(SyntheticScene, ObjectsOnTableWithoutOverlap) {
  int scenes_with_mug = 0, scenes_with_jar_or_can = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SceneOptions opt;
    opt.distractors = true;
    const auto s = mereo::synthetic::generate_scene(seed, opt);
    int on_table = 0;
    bool mug = false, jar = false;
    struct Fp { double x, y, r; std::string model; };
    std::vector<Fp> fps;
    for (const auto& o : s.objects) {
      if (o.model == "floor" || o.model == "wall" || o.model == "table") continue;
      if (o.model != "distractor") ++on_table;
      mug |= o.model == "mug";
      jar |= o.model == "jar" || o.model == "can";
      const Shape& first = o.parts.front().second;
      // every object stands on the table top (z = 0) and is above it
      double zmin = 1e9;
      for (const auto& [role, sh] : o.parts) {
        if (sh.cls == "cylinder") zmin = std::min(zmin, sh.point.z() - 0.5 * sh.height);
        if (sh.cls == "box") zmin = std::min(zmin, sh.point.z() - 0.5 * sh.size.z());
        if (sh.cls == "sphere") zmin = std::min(zmin, sh.point.z() + sh.height_min);
        if (sh.cls == "torus" && o.model == "distractor") zmin = std::min(zmin, sh.point.z());
      }
      EXPECT_NEAR(zmin, 0.0, 1e-9) << o.model << " seed " << seed;
      (void)first;
    }
    EXPECT_GE(on_table, 3) << "seed " << seed;
    EXPECT_LE(on_table, 6) << "seed " << seed;
    scenes_with_mug += mug;
    scenes_with_jar_or_can += jar;

    // distractors: 1-2.5 cm from the nearest jar wall, never touching it
    for (const auto& o : s.objects) {
      if (o.model != "distractor") continue;
      ASSERT_EQ(o.parts.size(), 1u);
      EXPECT_EQ(o.parts[0].first, "handle");
      const Shape& t = o.parts[0].second;
      double best = 1e9;
      for (const auto& j : s.objects) {
        if (j.model != "jar") continue;
        const Shape& body = j.parts.front().second;
        // sample the half ring's tube surface densely and measure the gap to the jar wall
        double gap = 1e9;
        const V3 e = t.axis.cross(t.axis2);
        for (int i = 0; i <= 180; ++i) {
          const double th = t.arc_start + (t.arc_end - t.arc_start) * i / 180.0;
          const V3 dir = std::cos(th) * t.axis2 + std::sin(th) * e;
          const V3 c = t.point + t.radius * dir;
          for (int k = 0; k < 36; ++k) {
            const double ph = 2 * kPi * k / 36;
            const V3 p = c + t.minor_radius * (std::cos(ph) * dir + std::sin(ph) * t.axis);
            if (p.z() < 0) continue;  // below the table top: not part of the object
            const V3 w = p - body.point;
            gap = std::min(gap, (w - w.dot(body.axis) * body.axis).norm() - body.radius);
          }
        }
        best = std::min(best, gap);
      }
      EXPECT_GT(best, 0.0095) << "seed " << seed;
      EXPECT_LT(best, 0.0255) << "seed " << seed;
    }
  }
  EXPECT_GE(scenes_with_mug, 28);
  EXPECT_GE(scenes_with_jar_or_can, 20);
}

TEST(SyntheticRender, MugBodyAndHandleLieOnAnalyticSurfaces) {
  int seeds_with_handle = 0, seeds_with_mug = 0;
  for (const auto seed : kSeeds) {
    const SyntheticFrame f = mereo::synthetic::render(seed, clean_options());
    const GroundTruth& gt = f.truth;
    const auto& K = f.frame.intrinsics;
    const int W = gt.depth.cols(), H = gt.depth.rows();
    bool handle_seen = false;
    for (const ObjectTruth& o : gt.objects_truth) {
      if (o.model != "mug") continue;
      const PartTruth* body = o.part("body");
      const PartTruth* handle = o.part("handle");
      ASSERT_NE(body, nullptr);
      ASSERT_NE(handle, nullptr);
      EXPECT_EQ(body->camera.cls, "cylinder");
      EXPECT_EQ(handle->camera.cls, "torus");
      std::size_t n_body = 0, n_handle = 0;
      double worst_body = 0, worst_handle = 0, worst_body_n = 0, worst_handle_n = 0;
      for (int v = 0; v < H; ++v) {
        for (int u = 0; u < W; ++u) {
          const std::uint32_t label = gt.parts(v, u);
          if (label != body->label && label != handle->label) continue;
          EXPECT_EQ(gt.objects(v, u), o.id);
          const double z = gt.depth(v, u);
          ASSERT_TRUE(std::isfinite(z));
          const V3 p = back_project(K, u, v, z);
          V3 n_exact;
          if (label == body->label) {
            double axial = 0;
            const double dist = cylinder_distance(body->camera, p, axial, n_exact);
            worst_body = std::max(worst_body, std::abs(dist));
            EXPECT_LE(std::abs(axial), 0.5 * body->camera.height + 0.0005);
            if (n_exact.dot(p) > 0) n_exact = -n_exact;
            worst_body_n = std::max(worst_body_n, angle_deg(normal_at(gt, u, v), n_exact));
            ++n_body;
          } else {
            const double dist = torus_distance(handle->camera, p, n_exact);
            worst_handle = std::max(worst_handle, std::abs(dist));
            // the rendered tube is outside the body cylinder
            double axial = 0;
            V3 unused;
            EXPECT_GT(cylinder_distance(body->camera, p, axial, unused), -0.0005);
            if (n_exact.dot(p) > 0) n_exact = -n_exact;
            worst_handle_n = std::max(worst_handle_n, angle_deg(normal_at(gt, u, v), n_exact));
            ++n_handle;
          }
        }
      }
      EXPECT_EQ(n_body, body->visible_pixels);
      EXPECT_EQ(n_handle, handle->visible_pixels);
      EXPECT_LT(worst_body, 0.0005) << "seed " << seed << " mug " << o.id;
      EXPECT_LT(worst_handle, 0.0005) << "seed " << seed << " mug " << o.id;
      EXPECT_LT(worst_body_n, 1.0) << "seed " << seed << " mug " << o.id;
      EXPECT_LT(worst_handle_n, 1.0) << "seed " << seed << " mug " << o.id;
      // a mug that is visible at all shows plenty of its body
      if (o.visible_pixels > 300) {
        EXPECT_GT(n_body, 100u) << "seed " << seed << " mug " << o.id;
      }
      if (n_handle > 0) handle_seen = true;
      std::cout << "[ info     ] seed " << seed << " mug " << o.id << ": " << n_body
                << " body pixels (max |d| " << worst_body * 1e3 << " mm, normal "
                << worst_body_n << " deg), " << n_handle << " handle pixels (max |d| "
                << worst_handle * 1e3 << " mm, normal " << worst_handle_n << " deg)\n";
    }
    // the first object on the table (index 3: after floor, wall, table) is usually a mug,
    // placed near the centre: it must be in view
    const ObjectTruth& first = gt.objects_truth.at(3);
    if (first.model == "mug") {
      ++seeds_with_mug;
      EXPECT_GT(first.part("body")->visible_pixels, 100u) << "seed " << seed;
    }
    seeds_with_handle += handle_seen;
  }
  EXPECT_GE(seeds_with_mug, 6);
  EXPECT_GE(seeds_with_handle, seeds_with_mug - 2);
  EXPECT_GE(seeds_with_handle, 5);
}

TEST(SyntheticRender, TruthNormalsDepthsAndLabelsAreConsistent) {
  for (const auto seed : kSeeds) {
    const SyntheticFrame f = mereo::synthetic::render(seed, clean_options());
    const GroundTruth& gt = f.truth;
    const auto& K = f.frame.intrinsics;
    const int W = gt.depth.cols(), H = gt.depth.rows();
    ASSERT_EQ(W, 640);
    ASSERT_EQ(H, 480);
    ASSERT_TRUE(f.frame.color.same_size(f.frame.depth));
    std::size_t table = 0, labelled = 0;
    const ObjectTruth* table_obj = nullptr;
    for (const auto& o : gt.objects_truth)
      if (o.model == "table") table_obj = &o;
    ASSERT_NE(table_obj, nullptr);
    for (int v = 0; v < H; ++v) {
      for (int u = 0; u < W; ++u) {
        const float z = gt.depth(v, u);
        if (std::isnan(z)) {
          EXPECT_EQ(gt.objects(v, u), 0u);
          continue;
        }
        ++labelled;
        EXPECT_NE(gt.objects(v, u), 0u);
        EXPECT_NE(gt.parts(v, u), 0u);
        EXPECT_EQ(f.frame.depth(v, u), z);  // no noise: the frame depth is the clean depth
        const V3 n = normal_at(gt, u, v);
        EXPECT_NEAR(n.norm(), 1.0, 1e-5);
        EXPECT_LT(n.dot(back_project(K, u, v, z)), 0.0);
        if (gt.objects(v, u) == table_obj->id) ++table;
      }
    }
    EXPECT_EQ(table, table_obj->visible_pixels);
    EXPECT_GT(labelled, std::size_t(W) * H * 99 / 100);  // floor and wall fill the background
    EXPECT_GT(double(table) / (W * H), 0.20) << "seed " << seed;
    // the table top (world z = 0) seen from above: top pixels are at world z = 0, normal +z
    const PartTruth* top = table_obj->part("top");
    ASSERT_NE(top, nullptr);
    const mereo::Pose T = gt.camera_pose;
    double worst = 0;
    for (int v = 0; v < H; v += 4)
      for (int u = 0; u < W; u += 4) {
        if (gt.parts(v, u) != top->label) continue;
        const V3 pw = T * back_project(K, u, v, gt.depth(v, u));
        const V3 nw = T.linear() * normal_at(gt, u, v);
        if (nw.z() > 0.99) worst = std::max(worst, std::abs(pw.z()));
      }
    EXPECT_LT(worst, 0.0005);
  }
}

TEST(SyntheticRender, OtherShapesLieOnTheirSurfaces) {
  // every kind of part (cylinders, discs, spheres, boxes, planes, tori) is checked analytically
  for (const auto seed : kSeeds) {
    SceneOptions opt = clean_options();
    opt.distractors = true;
    const SyntheticFrame f = mereo::synthetic::render(seed, opt);
    const GroundTruth& gt = f.truth;
    const auto& K = f.frame.intrinsics;
    std::vector<const PartTruth*> by_label(1, nullptr);
    for (const auto& o : gt.objects_truth)
      for (const auto& p : o.parts) {
        if (by_label.size() <= p.label) by_label.resize(p.label + 1, nullptr);
        by_label[p.label] = &p;
      }
    for (int v = 0; v < gt.depth.rows(); v += 2) {
      for (int u = 0; u < gt.depth.cols(); u += 2) {
        const std::uint32_t label = gt.parts(v, u);
        if (label == 0) continue;
        const Shape& s = by_label.at(label)->camera;
        const double z = gt.depth(v, u);
        const V3 p = back_project(K, u, v, z);
        const double tol = 0.0005 + 1e-6 * z * z;  // float depth rounding far away
        double dist = 0;
        if (s.cls == "plane" || s.cls == "disc") {
          dist = (p - s.point).dot(s.axis);
          if (s.cls == "disc") {
            const V3 w = p - s.point;
            const double r = (w - w.dot(s.axis) * s.axis).norm();
            EXPECT_LE(r, s.radius + 0.0005);
            EXPECT_GE(r, s.minor_radius - 0.0005);
          }
        } else if (s.cls == "cylinder") {
          double axial = 0;
          V3 n;
          dist = cylinder_distance(s, p, axial, n);
          EXPECT_LE(std::abs(axial), 0.5 * s.height + 0.0005);
        } else if (s.cls == "sphere") {
          dist = (p - s.point).norm() - s.radius;
          const double off = (p - s.point).dot(s.axis);
          EXPECT_GE(off, s.height_min - 0.0005);
          EXPECT_LE(off, s.height_max + 0.0005);
        } else if (s.cls == "torus") {
          V3 n;
          dist = torus_distance(s, p, n);
        } else if (s.cls == "box") {
          const V3 w = p - s.point;
          const V3 e = s.axis.cross(s.axis2);
          const V3 q(w.dot(s.axis2), w.dot(e), w.dot(s.axis));
          // on the surface: inside the box and on one face
          double face = 1e9;
          for (int i = 0; i < 3; ++i) {
            EXPECT_LE(std::abs(q[i]), 0.5 * s.size[i] + tol);
            face = std::min(face, std::abs(std::abs(q[i]) - 0.5 * s.size[i]));
          }
          dist = face;
        }
        EXPECT_LT(std::abs(dist), tol) << "seed " << seed << " class " << s.cls << " role "
                                       << by_label.at(label)->role;
      }
    }
  }
}

TEST(SyntheticRender, DeterministicWithNoise) {
  const SyntheticFrame a = mereo::synthetic::render(7);
  const SyntheticFrame b = mereo::synthetic::render(7);
  const SyntheticFrame c = mereo::synthetic::render(8);
  ASSERT_TRUE(a.frame.depth.same_size(b.frame.depth));
  EXPECT_EQ(std::memcmp(a.frame.depth.data(), b.frame.depth.data(),
                        a.frame.depth.size() * sizeof(float)),
            0);
  EXPECT_EQ(std::memcmp(a.frame.color.data(), b.frame.color.data(), a.frame.color.size()), 0);
  EXPECT_EQ(std::memcmp(a.truth.parts.data(), b.truth.parts.data(),
                        a.truth.parts.size() * sizeof(std::uint32_t)),
            0);
  EXPECT_NE(std::memcmp(a.frame.depth.data(), c.frame.depth.data(),
                        a.frame.depth.size() * sizeof(float)),
            0);
  EXPECT_EQ(a.frame.source, "synthetic:7");
  EXPECT_EQ(a.frame.id, "0000");
  ASSERT_TRUE(a.frame.pose.has_value());
  EXPECT_TRUE(a.frame.pose->isApprox(a.truth.camera_pose));
  EXPECT_TRUE(a.frame.cloud.empty());
  EXPECT_TRUE(a.frame.labels.empty());
}

TEST(SyntheticRender, SameResultOnOneThread) {
  const SyntheticFrame a = mereo::synthetic::render(21);
  SyntheticFrame b;
  tbb::task_arena one(1);
  one.execute([&] { b = mereo::synthetic::render(21); });
  EXPECT_EQ(std::memcmp(a.frame.depth.data(), b.frame.depth.data(),
                        a.frame.depth.size() * sizeof(float)),
            0);
  EXPECT_EQ(std::memcmp(a.truth.normals.data(), b.truth.normals.data(),
                        a.truth.normals.size() * sizeof(float)),
            0);
  EXPECT_EQ(std::memcmp(a.frame.color.data(), b.frame.color.data(), a.frame.color.size()), 0);
}

TEST(SyntheticRender, NoiseIsKinectLike) {
  std::size_t total_missing = 0;
  for (const std::uint64_t seed : {3ull, 11ull, 12ull}) {
    SceneOptions opt;
    opt.min_distance = opt.max_distance = 1.0;  // ~1 m to the table centre
    const SyntheticFrame f = mereo::synthetic::render(seed, opt);
    const GroundTruth& gt = f.truth;
    const ObjectTruth* table = nullptr;
    for (const auto& o : gt.objects_truth)
      if (o.model == "table") table = &o;
    ASSERT_NE(table, nullptr);
    const PartTruth* top = table->part("top");
    std::vector<double> dz;
    std::size_t missing = 0, clean_valid = 0, top_pixels = 0, top_present = 0;
    for (int v = 0; v < gt.depth.rows(); ++v) {
      for (int u = 0; u < gt.depth.cols(); ++u) {
        const float z0 = gt.depth(v, u), z = f.frame.depth(v, u);
        if (std::isnan(z0)) {
          EXPECT_TRUE(std::isnan(z));
          continue;
        }
        ++clean_valid;
        if (gt.parts(v, u) == top->label) {
          ++top_pixels;
          top_present += !std::isnan(z);
        }
        if (std::isnan(z)) {
          ++missing;
          continue;
        }
        if (z0 > 0.8 && z0 < 1.2) dz.push_back(std::abs(double(z) - z0));
      }
    }
    ASSERT_GT(dz.size(), 1000u);
    std::nth_element(dz.begin(), dz.begin() + dz.size() / 2, dz.end());
    const double median = dz[dz.size() / 2];
    EXPECT_GT(median, 0.0005) << "seed " << seed;
    EXPECT_LT(median, 0.010) << "seed " << seed;
    EXPECT_GT(missing, 0u);
    EXPECT_LT(missing, clean_valid / 4);
    EXPECT_GT(top_pixels, std::size_t(640 * 480) / 10);
    EXPECT_GT(double(top_present) / top_pixels, 0.85) << "seed " << seed;
    total_missing += missing;
    std::cout << "[ info     ] seed " << seed << ": median |dz| at ~1 m " << median * 1000
              << " mm, missing " << 100.0 * missing / clean_valid << " %, table top present "
              << 100.0 * top_present / top_pixels << " %\n";
  }
  EXPECT_GT(total_missing, 300u);
}

TEST(SyntheticRender, ProjectorShadowBesideObjects) {
  // the projector is to the right of the camera (+x): it casts the shadow of a near object on
  // the background to the object's left in the image, so more depth is missing just left of a
  // near object's left edge than just right of its right edge
  std::size_t right = 0, left = 0;
  for (const auto seed : kSeeds) {
    const SyntheticFrame f = mereo::synthetic::render(seed);
    const auto& gt = f.truth;
    for (int v = 0; v < gt.depth.rows(); ++v)
      for (int u = 3; u + 3 < gt.depth.cols(); ++u) {
        const float a = gt.depth(v, u), b = gt.depth(v, u + 1);
        if (std::isnan(a) || std::isnan(b)) continue;
        // near -> far going right: the far side at u+3 is in the projector's shadow?
        if (b - a > 0.1f * a && std::isnan(f.frame.depth(v, u + 3))) ++right;
        // far -> near going right: left of the near object's left edge
        if (a - b > 0.1f * b && std::isnan(f.frame.depth(v, u - 2))) ++left;
      }
  }
  EXPECT_GT(left, 2 * right + 50);
}

TEST(SyntheticRender, SequenceOrbitsTheTable) {
  SceneOptions opt;
  opt.noise = false;
  const auto frames = mereo::synthetic::render_sequence(5, 5, opt);
  const auto scene = mereo::synthetic::generate_scene(5, opt);
  ASSERT_EQ(frames.size(), 5u);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& f = frames[i];
    ASSERT_TRUE(f.frame.pose.has_value());
    const mereo::Pose& T = *f.frame.pose;
    EXPECT_NEAR((T.translation() - scene.look_at).norm(), scene.camera_distance, 1e-9);
    // the optical axis points at look_at and x is horizontal (no roll)
    const V3 fwd = T.linear().col(2);
    EXPECT_NEAR(fwd.dot((scene.look_at - T.translation()).normalized()), 1.0, 1e-9);
    EXPECT_NEAR(T.linear().col(0).z(), 0.0, 1e-9);
    EXPECT_GT(T.linear().col(1).dot(-V3::UnitZ()), 0.0);  // image y points down-ish
    EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-9);
    EXPECT_EQ(f.frame.id, std::string("000") + char('0' + i));
    EXPECT_DOUBLE_EQ(f.frame.timestamp, i / 30.0);
    for (std::size_t j = 0; j < i; ++j) {
      const double step = (T.translation() - frames[j].frame.pose->translation()).norm();
      EXPECT_GT(step, 0.01);
    }
    if (i > 0) {
      // the orbit step in azimuth
      const V3 a = T.translation() - scene.look_at, b = frames[i - 1].frame.pose->translation() - scene.look_at;
      const double az = std::atan2(a.y(), a.x()) - std::atan2(b.y(), b.x());
      EXPECT_NEAR(std::remainder(az, 2 * kPi), opt.orbit_step_deg * kPi / 180.0, 1e-9);
    }
    // the same scene in every frame: the same world parameters
    EXPECT_EQ(f.truth.objects_truth.size(), frames[0].truth.objects_truth.size());
    EXPECT_EQ(f.truth.objects_truth.back().parts.front().world.point,
              frames[0].truth.objects_truth.back().parts.front().world.point);
  }
}

TEST(SyntheticRender, OrbitPoseConvention) {
  const mereo::Pose T = mereo::synthetic::orbit_pose(V3::Zero(), 1.0, 90.0 - 1e-9, 0.0);
  // nearly straight down: forward is -z
  EXPECT_NEAR(T.linear().col(2).z(), -1.0, 1e-6);
  const mereo::Pose S = mereo::synthetic::orbit_pose(V3(0.1, 0.2, 0.0), 2.0, 0.0, 0.0);
  // from +x looking towards -x, level: right is +y world, down is -z world
  EXPECT_TRUE(S.translation().isApprox(V3(2.1, 0.2, 0.0)));
  EXPECT_TRUE(S.linear().col(2).isApprox(V3(-1, 0, 0)));
  EXPECT_TRUE(S.linear().col(0).isApprox(V3(0, 1, 0)));
  EXPECT_TRUE(S.linear().col(1).isApprox(V3(0, 0, -1)));
}

TEST(SyntheticRender, TruthJson) {
  SceneOptions opt = clean_options();
  opt.distractors = true;
  const SyntheticFrame f = mereo::synthetic::render(4, opt);
  const auto j = nlohmann::json::parse(mereo::synthetic::truth_to_json(f));
  EXPECT_EQ(j["frame"], "0000");
  EXPECT_EQ(j["source"], "synthetic:4");
  EXPECT_EQ(j["intrinsics"]["width"], 640);
  EXPECT_EQ(j["intrinsics"]["fx"], 525.0);
  ASSERT_EQ(j["camera_pose"].size(), 4u);
  EXPECT_EQ(j["camera_pose"][3][3], 1.0);
  EXPECT_DOUBLE_EQ(j["camera_pose"][0][3].get<double>(), f.truth.camera_pose.translation().x());
  ASSERT_EQ(j["objects"].size(), f.truth.objects_truth.size());
  bool saw_cylinder = false;
  for (std::size_t i = 0; i < j["objects"].size(); ++i) {
    const auto& jo = j["objects"][i];
    const auto& o = f.truth.objects_truth[i];
    EXPECT_EQ(jo["id"], o.id);
    EXPECT_EQ(jo["model"], o.model);
    EXPECT_EQ(jo["visible_pixels"], o.visible_pixels);
    ASSERT_EQ(jo["parts"].size(), o.parts.size());
    for (std::size_t k = 0; k < o.parts.size(); ++k) {
      const auto& jp = jo["parts"][k];
      EXPECT_EQ(jp["role"], o.parts[k].role);
      EXPECT_EQ(jp["class"], o.parts[k].world.cls);
      EXPECT_EQ(jp["label"], o.parts[k].label);
      if (o.parts[k].world.cls == "cylinder") {
        saw_cylinder = true;
        EXPECT_DOUBLE_EQ(jp["camera"]["radius"].get<double>(), o.parts[k].camera.radius);
        EXPECT_DOUBLE_EQ(jp["camera"]["point"][2].get<double>(), o.parts[k].camera.point.z());
        EXPECT_DOUBLE_EQ(jp["world"]["height"].get<double>(), o.parts[k].world.height);
      }
      if (o.parts[k].world.cls == "torus") {
        EXPECT_TRUE(jp["camera"].contains("major_radius"));
        EXPECT_TRUE(jp["camera"].contains("normal"));
      }
    }
  }
  EXPECT_TRUE(saw_cylinder);
}

TEST(SyntheticRender, BadOptionsThrow) {
  SceneOptions opt;
  opt.min_objects = 5;
  opt.max_objects = 2;
  EXPECT_ANY_THROW(mereo::synthetic::generate_scene(1, opt));
  opt = SceneOptions();
  opt.min_distance = -1;
  EXPECT_ANY_THROW(mereo::synthetic::generate_scene(1, opt));
}

TEST(SyntheticRender, TimePerVgaFrame) {
  const auto scene = mereo::synthetic::generate_scene(9);
  const auto pose = mereo::synthetic::orbit_pose(scene.look_at, scene.camera_distance,
                                                 scene.camera_elevation_deg,
                                                 scene.camera_azimuth_deg);
  for (const bool noise : {false, true}) {
    SceneOptions opt;
    opt.noise = noise;
    mereo::synthetic::render(scene, pose, opt);  // warm up
    const int n = 5;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) mereo::synthetic::render(scene, pose, opt, i);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
    std::cout << "[ timing   ] synthetic VGA frame " << (noise ? "with" : "without")
              << " noise: " << ms << " ms\n";
  }
}

// Rooms: the furniture stands where the generator put it (a chair's seat 0.42-0.50 m above the
// floor, a table's top 0.40-0.76 m), every pixel is labelled (floor and walls fill the rest), each
// object's and each part's visible pixels are at most those it would cover alone (a part: its own
// object's other parts count as in front, so that a chair in full view whose back hides its seat
// shows that seat partly hidden), and the same seed gives the same room.
TEST(SyntheticRoom, FurnitureOnTheFloorWithItsHiddenShareCounted) {
  SceneOptions o = clean_options();
  o.room = true;
  std::size_t seats_hidden_by_their_back = 0;
  for (const std::uint64_t seed : {9000u, 9001u, 9002u, 9003u}) {
    const auto scene = mereo::synthetic::generate_scene(seed, o);
    EXPECT_TRUE(scene.room);
    const SyntheticFrame f = mereo::synthetic::render(seed, o);
    const GroundTruth& gt = f.truth;
    std::size_t chairs = 0, tables = 0, doors = 0, labelled = 0;
    for (std::size_t i = 0; i < gt.objects.pixels(); ++i) labelled += gt.objects.data()[i] != 0;
    EXPECT_EQ(labelled, gt.objects.pixels()) << "seed " << seed;
    for (const auto& obj : gt.objects_truth) {
      EXPECT_LE(obj.visible_pixels, obj.unoccluded_pixels) << obj.model << ", seed " << seed;
      for (const auto& p : obj.parts) {
        EXPECT_LE(p.visible_pixels, p.unoccluded_pixels) << obj.model << "." << p.role << ", seed " << seed;
        EXPECT_LE(p.unoccluded_pixels, obj.unoccluded_pixels) << obj.model << "." << p.role << ", seed " << seed;
      }
      if (obj.model == "chair") {
        ++chairs;
        const PartTruth* seat = obj.part("seat");
        ASSERT_NE(seat, nullptr);
        // nothing in front of the chair, yet its seat partly hidden: by its own back
        seats_hidden_by_their_back += obj.visible_pixels == obj.unoccluded_pixels && seat->visible_pixels < 0.9 * seat->unoccluded_pixels;
        const double top = seat->world.point.z() + 0.5 * seat->world.size.z();
        EXPECT_GE(top, 0.42 - 1e-9);
        EXPECT_LE(top, 0.50 + 1e-9);
        ASSERT_NE(obj.part("back"), nullptr);
      }
      if (obj.model == "table") {
        ++tables;
        const PartTruth* top = obj.part("top");
        ASSERT_NE(top, nullptr);
        const double h = top->world.point.z() + 0.5 * top->world.size.z();
        EXPECT_TRUE((h >= 0.40 && h <= 0.48) || (h >= 0.72 && h <= 0.76)) << h;
      }
      doors += obj.model == "door";
    }
    EXPECT_GE(chairs, 1u);
    EXPECT_EQ(tables, 1u);
    EXPECT_EQ(doors, 1u);
    // the same seed, the same room
    const SyntheticFrame again = mereo::synthetic::render(seed, o);
    EXPECT_EQ(std::memcmp(again.truth.objects.data(), gt.objects.data(), gt.objects.pixels() * sizeof(std::uint32_t)), 0);
  }
  EXPECT_GE(seats_hidden_by_their_back, 2u);  // 9001 and 9003: seen from behind (0.75 of each seat)
}
