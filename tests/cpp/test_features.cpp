// The feature layer (work in progress, issue 5): minimal-set solvers recover exact shapes from
// exact samples, the least-squares refit recovers them from noisy points, and detection finds
// the bodies of a clean rendered scene with their true radii. Bad input is an error.
#include <gtest/gtest.h>

#include <optional>
#include <random>

#include "features/fit.hpp"
#include "features/pixels.hpp"
#include "mereo/core/error.hpp"
#include "mereo/extension/normals.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/primitives.hpp"
#include "mereo/features/patches.hpp"
#include "mereo/features/regions.hpp"
#include "mereo/signal/depth_filter.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
namespace fd = mereo::features::detail;

namespace {

Segment torus(Eigen::Vector3d c, Eigen::Vector3d n, double R, double r) {
  return Segment(shapes::Torus{c, n.normalized(), R, r});
}

Segment cylinder(Eigen::Vector3d point, Eigen::Vector3d axis, double radius, double height = 0.0) {
  return Segment(shapes::Cylinder{point, axis.normalized(), radius, height});
}

/// A point of the torus at ring angle a and tube angle b, and its outward normal.
std::pair<Eigen::Vector3d, Eigen::Vector3d> torus_point(const Segment& s, double a, double b) {
  const auto& t = s.as<shapes::Torus>();
  Eigen::Vector3d e1 = t.normal.unitOrthogonal(), e2 = t.normal.cross(e1);
  const Eigen::Vector3d radial = std::cos(a) * e1 + std::sin(a) * e2;
  const Eigen::Vector3d normal = std::cos(b) * radial + std::sin(b) * t.normal;
  return {t.center + t.major_radius * radial + t.minor_radius * normal, normal};
}

/// What a depth sensor sees of `s` (a cylinder within half_height of s.point along its axis, or
/// a sphere): for each VGA pixel (f = 525) whose ray meets it at under 80 degrees of incidence,
/// the point where it does, on the surface facing the camera (the near crossing of an outer
/// wall, the far one of an inner wall, s.inward), with its depth moved by Gaussian noise of
/// sigma_z: the axial noise of structured-light sensors.
std::vector<Eigen::Vector3d> sensed(const Segment& s, double half_height, double sigma_z, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma_z);
  std::vector<Eigen::Vector3d> out;
  const auto* C = s.get_if<shapes::Cylinder>();
  const bool cyl = C != nullptr;
  const Eigen::Vector3d centre = s.origin(), axis = cyl ? C->axis : Eigen::Vector3d::UnitZ();
  const double radius = s.size();
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const Eigen::Vector3d d = Eigen::Vector3d((u - 319.5) / 525, (v - 239.5) / 525, 1).normalized();
      const Eigen::Vector3d w = cyl ? Eigen::Vector3d(d - axis * axis.dot(d)) : d;
      const Eigen::Vector3d c = cyl ? Eigen::Vector3d(centre - axis * axis.dot(centre)) : centre;
      const double A = w.squaredNorm(), B = w.dot(c), C = c.squaredNorm() - radius * radius;
      const double disc = B * B - A * C;
      if (!(disc > 0)) continue;
      const double t = (B + (s.inward ? 1 : -1) * std::sqrt(disc)) / A;
      const Eigen::Vector3d x = t * d;
      if (cyl && std::abs(axis.dot(x - centre)) > half_height) continue;
      Eigen::Vector3d n = x - centre;
      if (cyl) n -= axis * axis.dot(n);
      if (std::abs(n.normalized().dot(d)) < std::cos(80 * M_PI / 180)) continue;
      out.push_back((t + noise(rng) / d.z()) * d);
    }
  return out;
}

}  // namespace

TEST(Features, MinimalSetsAreExactOnExactSamples) {
  // cylinder: axis (0.2, -1, 0.1), radius 4 cm
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -1, 0.1).normalized(), c(0.05, 0.02, 0.9);
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  auto on_cyl = [&](double a, double h) {
    const Eigen::Vector3d n = std::cos(a) * e1 + std::sin(a) * e2;
    return std::make_pair(Eigen::Vector3d(c + 0.04 * n + h * axis), n);
  };
  const auto [p1, n1] = on_cyl(0.3, 0.01);
  const auto [p2, n2] = on_cyl(1.4, -0.03);
  const shapes::Limits limits;
  auto two = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& na, const Eigen::Vector3d& b, const Eigen::Vector3d& nb) {
    static thread_local Eigen::Vector3d P[2], N[2];
    P[0] = a, P[1] = b, N[0] = na, N[1] = nb;
    return std::make_pair(P, N);
  };
  auto [cp, cn] = two(p1, n1, p2, n2);
  const auto cyl = shapes::Cylinder::from_sample(cp, cn, limits);
  ASSERT_TRUE(cyl);
  EXPECT_NEAR(cyl->radius, 0.04, 1e-9);
  EXPECT_NEAR(std::abs(cyl->axis.dot(axis)), 1.0, 1e-9);
  EXPECT_NEAR(cyl->signed_distance(c + 0.04 * e1 + 0.07 * axis), 0.0, 1e-9);
  // sphere
  const Eigen::Vector3d sc(0.1, 0, 1.0), d1 = Eigen::Vector3d(0.3, -0.2, -1).normalized(),
                        d2 = Eigen::Vector3d(-0.4, 0.1, -1).normalized();
  auto [sp, sn] = two(sc + 0.08 * d1, d1, sc + 0.08 * d2, d2);
  const auto sph = shapes::Sphere::from_sample(sp, sn, limits);
  ASSERT_TRUE(sph);
  EXPECT_NEAR(sph->radius, 0.08, 1e-9);
  EXPECT_NEAR((sph->center - sc).norm(), 0.0, 1e-9);
  // torus (a mug handle: ring 2.5 cm, tube 6 mm)
  const Segment t = torus({0.0, 0.0, 0.8}, {0.3, 0.1, 1.0}, 0.025, 0.006);
  Eigen::Vector3d P[4], N[4];
  const double ab[4][2] = {{0.1, 0.3}, {0.9, -1.0}, {1.8, 2.0}, {2.7, 0.5}};
  for (int k = 0; k < 4; ++k) std::tie(P[k], N[k]) = torus_point(t, ab[k][0], ab[k][1]);
  shapes::Limits tube;
  tube.min_minor_radius = 0.003, tube.max_minor_radius = 0.02;
  const auto tor = shapes::Torus::from_sample(P, N, tube);
  ASSERT_TRUE(tor);
  EXPECT_NEAR(tor->minor_radius, 0.006, 1e-7);
  EXPECT_NEAR(tor->major_radius, 0.025, 1e-7);
  EXPECT_NEAR((tor->center - t.origin()).norm(), 0.0, 1e-7);
  EXPECT_NEAR(std::abs(tor->normal.dot(*t.direction())), 1.0, 1e-9);
  // degenerate: parallel normals give no cylinder
  auto [dp, dn] = two(p1, n1, p1 + 0.01 * axis, n1);
  EXPECT_FALSE(shapes::Cylinder::from_sample(dp, dn, limits));
}

TEST(Features, RefitRecoversShapesFromNoisyPoints) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const Segment t = torus({0.02, -0.01, 0.9}, {0.1, 0.2, 1.0}, 0.027, 0.007);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 400; ++i) {
    auto [p, n] = torus_point(t, 3 * U(rng), 1.5 * U(rng));
    pts.push_back(p + n * noise(rng));
  }
  Segment start = t;
  auto& S = start.as<shapes::Torus>();
  S.center += Eigen::Vector3d(0.003, -0.002, 0.002);
  S.major_radius *= 1.1, S.minor_radius *= 0.8;
  S.normal = (S.normal + Eigen::Vector3d(0.05, 0, 0)).normalized();
  const Segment fit = fd::refit_points(start, pts);
  EXPECT_NEAR(fit.as<shapes::Torus>().major_radius, 0.027, 5e-4);
  EXPECT_NEAR(fit.as<shapes::Torus>().minor_radius, 0.007, 5e-4);
  EXPECT_LT((fit.origin() - t.origin()).norm(), 1e-3);
  EXPECT_LT(fit.residual, 0.0008);
}

// A depth sensor's noise lies along the rays. A geometric fit to a curved surface under it is
// biased (its radius comes out too small, growing with the noise: ~0.7 mm for a 4 cm cylinder
// at 1.3 m); the fit along the rays is the maximum-likelihood one and is not.
TEST(Features, RefitAlongTheRaysIsUnbiasedUnderAxialNoise) {
  std::mt19937_64 rng(11);
  const Segment outer = cylinder({0.06, 0.05, 1.3}, {0.05, -0.8, 0.6}, 0.04);
  Segment inner = cylinder({0.06, 0.05, 1.3}, {0.05, -0.8, 0.6}, 0.06);  // the far inside wall of a wider
  inner.inward = true;                                                  // cylinder, seen through its open side
  const Segment ball(shapes::Sphere{Eigen::Vector3d(-0.05, 0.02, 1.2), 0.05});
  for (const Segment& truth : {outer, inner, ball}) {
    double geometric = 0, along = 0;
    const int trials = 12;
    for (int k = 0; k < trials; ++k) {
      const auto pts = sensed(truth, 0.05, 0.003, rng);  // sigma_z of a Kinect at ~1.3 m
      ASSERT_GT(pts.size(), 500u);
      Segment start = truth;
      start.set_field("point", Eigen::Vector3d(start.origin() + Eigen::Vector3d(0.002, -0.001, 0.002)));
      start.set_field("radius", start.size() + 0.002);
      geometric += fd::refit_points(start, pts).size() - truth.size();
      along += fd::refit_points(start, pts, fd::Residual::AlongRay).size() - truth.size();
    }
    geometric *= 1000.0 / trials, along *= 1000.0 / trials;  // mean signed errors, mm
    const std::string figures = std::string(truth.class_name()) + (truth.inward ? " (inner wall)" : "") +
                                ": mean radius error, geometric fit " + std::to_string(geometric) +
                                " mm, along the rays " + std::to_string(along) + " mm";
    std::printf("%s\n", figures.c_str());
    SCOPED_TRACE(figures);
    EXPECT_LT(std::abs(along), 0.1);
    EXPECT_GT(std::abs(geometric), 3 * std::abs(along));
  }
}

TEST(Features, DetectsTheBodiesOfACleanSceneWithTheirRadii) {
  synthetic::SceneOptions so;
  so.noise = false;
  int bodies = 0, found = 0;
  for (std::uint64_t seed : {0, 1, 2}) {
    const auto sf = synthetic::render(seed, so);
    const Cloud cloud = extension::back_project(sf.frame);
    const auto segs = features::detect_primitives(cloud, extension::estimate_normals(cloud));
    for (const auto& obj : sf.truth.objects_truth) {
      const auto* body = obj.part("body");
      if (!body || body->camera.cls != "cylinder" || body->visible_pixels < 1000) continue;
      if (obj.model != "mug" && obj.model != "jar" && obj.model != "can" && obj.model != "bottle") continue;
      ++bodies;
      for (const auto& s : segs)
        if (const auto* c = s.get_if<shapes::Cylinder>();
            c && std::abs(c->radius - body->camera.radius) < 0.002 &&
            std::abs(c->axis.dot(body->camera.axis)) > std::cos(2 * M_PI / 180) &&
            s.signed_distance(body->camera.point) < 0.0) {
          ++found;
          break;
        }
    }
  }
  EXPECT_GE(bodies, 4);
  EXPECT_EQ(found, bodies);
}

TEST(Features, BadInputIsAnError) {
  EXPECT_THROW(features::detect_primitives(Cloud(10, 10, 1.f), NormalMap(10, 12, 0.f)), InputError);
  features::DetectOptions o;
  o.epsilon = -1;
  EXPECT_THROW(features::detect_primitives(Cloud(10, 10, 1.f), NormalMap(10, 10, 0.f), o), InputError);
  // unfiltered points on another grid than the cloud's
  features::DetectOptions wrong_grid;
  wrong_grid.unfiltered = Cloud(10, 12, 1.f);
  EXPECT_THROW(features::detect_primitives(Cloud(10, 10, 1.f), NormalMap(10, 10, 0.f), wrong_grid), InputError);
  // an all-NaN frame: no segments, no crash
  EXPECT_TRUE(features::detect_primitives(Cloud(48, 64, kNaN), NormalMap(48, 64, kNaN)).empty());
}

// Recall against the renderer's exact part labels (the scoring of bench_primitives, on fewer
// frames): cylindrical bodies with >= 500 visible pixels, mug handles with >= 150 within 1.2 m.
#include "../bench/bench_util.hpp"
#include "../bench/eval_primitives.hpp"

TEST(Features, RecallOnNoisyRenderedScenes) {
  bench::SyntheticScore score;
  for (std::uint64_t seed = 900; seed < 908; ++seed) {
    const auto sf = synthetic::render(seed);
    const Cloud cloud = extension::back_project(sf.frame);
    const auto found = features::detect_primitives(cloud, extension::estimate_normals(cloud), {}, &sf.frame.color);
    bench::score_synthetic(sf.truth, found, "synthetic:" + std::to_string(seed), score);
  }
  ASSERT_GE(score.bodies, 20);
  ASSERT_GE(score.handles, 5);
  EXPECT_GE(score.body_recall(), 0.9);
  EXPECT_GE(score.handle_recall(), 0.8);
  EXPECT_LT(score.false_cylinders_per_frame(), 1.0);
  EXPECT_LT(bench::median(score.radius_err_mm), 2.0);
  EXPECT_LT(bench::median(score.axis_err_deg), 2.0);
}

// The pipeline filters depth before normals and segmentation; smoothing flattens a curved
// surface, so bodies fitted to the filtered points come out too wide. Given the unfiltered
// points, cylinders are measured on them: the mean signed radius error of the bodies stays
// within the noise's reach of zero.
TEST(Features, BodiesAreMeasuredOnTheUnfilteredDepth) {
  signal::DepthFilterOptions fo;
  fo.radius = 1;  // the tabletop graph's filter
  bench::SyntheticScore on_filtered, on_unfiltered;
  for (std::uint64_t seed = 900; seed < 908; ++seed) {
    const auto sf = synthetic::render(seed);
    const Cloud cloud = extension::back_project(signal::filter_depth(sf.frame, fo));
    const NormalMap normals = extension::estimate_normals(cloud);
    features::DetectOptions o;
    bench::score_synthetic(sf.truth, features::detect_primitives(cloud, normals, o), "filtered", on_filtered);
    o.unfiltered = extension::back_project(sf.frame);
    bench::score_synthetic(sf.truth, features::detect_primitives(cloud, normals, o), "unfiltered", on_unfiltered);
  }
  ASSERT_GE(on_unfiltered.radius_bias.size(), 20u);
  const double filtered = on_filtered.mean_radius_bias_mm(0, 10), unfiltered = on_unfiltered.mean_radius_bias_mm(0, 10);
  const std::string figures = "bodies' mean signed radius error: on the filtered points " + std::to_string(filtered) +
                              " mm, on the unfiltered " + std::to_string(unfiltered) + " mm (" +
                              std::to_string(on_unfiltered.radius_bias.size()) + " bodies)";
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  EXPECT_LT(std::abs(unfiltered), 0.08);
  EXPECT_GT(filtered, unfiltered + 0.1);
}

TEST(Features, HandleFitHoldsTheRingPlaneAndFacesTheCamera) {
  // a mug body along -y at 0.8 m, its handle's ring in the plane through the axis; only the
  // half of the tube that faces the camera is sampled, with 1 mm noise
  const Segment body = cylinder({0.0, 0.0, 0.8}, {0, -1, 0}, 0.04, 0.1);
  const auto& B = body.as<shapes::Cylinder>();
  const Segment truth = torus({0.055, 0.0, 0.8}, {0, 0, 1}, 0.025, 0.006);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::vector<Eigen::Vector3d> pts;
  for (double a = -1.4; a <= 1.4; a += 0.05)
    for (double b = -M_PI; b < M_PI; b += 0.3) {
      auto [p, n] = torus_point(truth, a, b);
      const double from_axis = Eigen::Vector2d(p.x() - B.point.x(), p.z() - B.point.z()).norm();
      if (n.dot(-p.normalized()) <= 0.1 || from_axis < B.radius) continue;  // seen, outside the body
      pts.push_back(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
  Segment start = truth;
  start.as<shapes::Torus>().center += Eigen::Vector3d(0.01, 0.008, 0.0);
  start.as<shapes::Torus>().major_radius = 0.02, start.as<shapes::Torus>().minor_radius = 0.006;
  const Segment fit = features::refit_handle(body, start, pts);
  EXPECT_NEAR(fit.as<shapes::Torus>().major_radius, 0.025, 0.002);
  EXPECT_NEAR(fit.as<shapes::Torus>().minor_radius, 0.006, 0.002);
  EXPECT_LT((fit.origin() - truth.origin()).norm(), 0.003);
  EXPECT_NEAR(std::abs(fit.direction()->dot(*truth.direction())), 1.0, 1e-3);
}

// A handle is attached to its body. Active-stereo depth at a metre moves a handle's points as a
// whole (errors correlated over ~9 pixels, edges fattened outwards): here its outer arc alone,
// pushed 8 mm off the axis, with 2 mm of noise. A free fit then gives a ring standing off the wall,
// which the model rejects (intersects); the handle fit keeps the tube's centre line entering the
// wall, with the ring radius near the truth.
TEST(Features, HandleFitKeepsTheRingAttachedToTheWall) {
  const Segment body = cylinder({0.0, 0.0, 1.0}, {0, -1, 0}, 0.04, 0.1);
  const double R = 0.028, r = 0.006;
  const Segment truth = torus({0.04 + R - r, 0.0, 1.0}, {0, 0, 1}, R, r);  // attached
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::vector<Eigen::Vector3d> pts;
  for (double a = -M_PI; a < M_PI; a += 0.06)
    for (double b = -M_PI; b < M_PI; b += 0.4) {
      auto [p, n] = torus_point(truth, a, b);
      const Eigen::Vector3d out(p.x(), 0.0, p.z() - 1.0);  // away from the axis
      if (n.dot(-p.normalized()) <= 0.1 || out.norm() < 0.04 + 0.02) continue;
      pts.push_back(p + 0.008 * out.normalized() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
  ASSERT_GT(pts.size(), 50u);
  const Segment start = torus({0.075, 0.0, 1.0}, {0, 0, 1}, 0.02, 0.006);
  for (bool fix_minor : {true, false}) {
    const auto& t = features::refit_handle(body, start, pts, fix_minor).as<shapes::Torus>();
    const double d = std::hypot(t.center.x(), t.center.z() - 1.0);
    SCOPED_TRACE("fix_minor " + std::to_string(fix_minor) + ": centre " + std::to_string(d) + " from the axis, ring " +
                 std::to_string(t.major_radius) + ", tube " + std::to_string(t.minor_radius));
    EXPECT_LE(d - t.major_radius, 0.04 + 1e-6);
    EXPECT_NEAR(t.major_radius, R, 0.008);
    EXPECT_NEAR(t.center.y(), 0.0, 0.004);
  }
}

TEST(Features, HandleTurnTellsAHandleFromARingTurnedAwayFromTheAxis) {
  // a ring beside a body along -y at 0.8 m, its plane turned about the body's axis by `beta`
  // (0: a handle's, through the axis; a ring leaning on a jar is turned 35-70 deg); the half of
  // the tube that faces the camera is seen, with 1 mm noise; the plane-held handle fit starts it
  const Segment body = cylinder({0.0, 0.0, 0.8}, {0, -1, 0}, 0.04, 0.1);
  const auto& B = body.as<shapes::Cylinder>();
  for (double beta : {0.0, 45.0, -60.0}) {
    const Eigen::Vector3d n = Eigen::AngleAxisd(beta * M_PI / 180, B.axis) * Eigen::Vector3d::UnitZ();
    // its centre from the axis: at beta 0 the tube's centre line enters the wall by 4 mm (attached)
    const double reach = 0.025 * std::cos(beta * M_PI / 180) + 0.036;
    const Segment truth = torus({reach, 0.0, 0.8}, n, 0.025, 0.006);
    std::mt19937_64 rng(6);
    std::normal_distribution<double> noise(0.0, 0.001);
    std::vector<Eigen::Vector3d> pts;
    for (double a = -M_PI; a < M_PI; a += 0.05)
      for (double b = -M_PI; b < M_PI; b += 0.3) {
        auto [p, pn] = torus_point(truth, a, b);
        const double from_axis = Eigen::Vector2d(p.x() - B.point.x(), p.z() - B.point.z()).norm();
        if (pn.dot(-p.normalized()) <= 0.1 || from_axis < B.radius + 0.002) continue;
        pts.push_back(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
      }
    const Segment held = features::refit_handle(body, torus({reach, 0.0, 0.8}, {0, 0, 1}, 0.025, 0.006), pts, true);
    const auto turn = features::handle_turn(body, held, pts);
    SCOPED_TRACE("beta " + std::to_string(beta));
    EXPECT_NEAR(std::abs(turn.turn_deg), std::abs(beta), 8.0);
    if (beta == 0.0) {
      EXPECT_GT(turn.rms_turned, 0.9 * turn.rms_held);  // nothing to gain: a handle
    } else {
      EXPECT_LT(turn.rms_turned, 0.6 * turn.rms_held);  // what the handle search rejects
    }
  }
}

/// The points of a handle's tube that a camera at the origin sees beside a body along y: the
/// side of the tube facing it, beyond the body's wall, each moved by `jitter`.
template <class Jitter>
std::vector<Eigen::Vector3d> seen_handle(const Segment& handle, const shapes::Cylinder& B, Jitter&& jitter) {
  std::vector<Eigen::Vector3d> out;
  for (double a = -M_PI; a < M_PI; a += 0.05)
    for (double b = -M_PI; b < M_PI; b += 0.4) {
      auto [p, pn] = torus_point(handle, a, b);
      const double from_axis = Eigen::Vector2d(p.x() - B.point.x(), p.z() - B.point.z()).norm();
      if (pn.dot(-p.normalized()) > 0.1 && from_axis > B.radius + 0.002) out.push_back(jitter(p));
    }
  return out;
}

TEST(Features, APatchOfTheBodysOwnWallIsNoHandle) {
  // a body along -y at 0.8 m; points with 2 mm noise on the side of its wall facing the camera, and
  // on the outer arc of a handle's tube (ring radius 2.5 cm, tube 6 mm, attached to the wall)
  const Segment body = cylinder({0.0, 0.0, 0.8}, {0, -1, 0}, 0.04, 0.1);
  const auto& B = body.as<shapes::Cylinder>();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.002);
  auto jitter = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))); };
  std::vector<Eigen::Vector3d> wall, handle;
  for (double a = -0.6; a <= 0.6; a += 0.05)  // azimuths about the axis facing the camera (-z)
    for (double y = -0.04; y <= 0.04; y += 0.005)
      wall.push_back(jitter({B.radius * std::sin(a), y, 0.8 - B.radius * std::cos(a)}));
  const Segment handle_torus = torus({0.061, 0.0, 0.8}, {0, 0, 1}, 0.025, 0.006);
  handle = seen_handle(handle_torus, B, jitter);
  const auto tolerance = [](double) { return 0.005; };
  // a torus fitted to the wall: centred inside the body (1 cm off the axis, as on the stereo
  // tapered cup of seed 5022), its points on the wall
  const Segment on_wall = torus({0.01, 0.0, 0.79}, {1, 0, 0}, 0.027, 0.008);
  EXPECT_TRUE(features::wall_patch(B, on_wall, wall, tolerance));
  // the handle: centred beyond the wall, its points off it
  EXPECT_FALSE(features::wall_patch(B, handle_torus, handle, tolerance));
  // a torus centred inside the body whose points stand off the wall (a pitcher's wide handle
  // fitted from its root) is kept; and one centred outside whatever its points
  EXPECT_FALSE(features::wall_patch(B, on_wall, handle, tolerance));
  EXPECT_FALSE(features::wall_patch(B, handle_torus, wall, tolerance));
}

TEST(Features, TheWiderRestOfATaperedWallIsNoHandle) {
  // a cup along -y at 1 m whose wall tapers by 8 degrees (radius 3.2 cm at its middle, wider
  // towards -y); the detector held its lower half as a cylinder of radius 3.2 cm, and its upper
  // half stands off that cylinder by up to 1 cm: a torus fitted there is the wall, not a handle.
  // 3 mm noise (active stereo at 1 m); the side of the wall facing the camera.
  const Segment body = cylinder({0.0, 0.0, 1.0}, {0, -1, 0}, 0.032, 0.05);
  const auto& B = body.as<shapes::Cylinder>();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.003);
  auto jitter = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng))); };
  const double k = std::tan(8 * M_PI / 180);
  auto on_cone = [&](double a, double y) {  // y along the image's -y = up the cup
    const double r = B.radius + k * (-y);
    return jitter({r * std::sin(a), y, 1.0 - r * std::cos(a)});
  };
  std::vector<Eigen::Vector3d> lower, upper, handle;
  for (double a = -0.7; a <= 0.7; a += 0.05) {
    for (double y = 0.045; y >= 0.0; y -= 0.004) lower.push_back(on_cone(a, y));
    for (double y = -0.004; y >= -0.045; y -= 0.004) upper.push_back(on_cone(a, y));
  }
  // a mug's handle on the same body (ring radius 2.5 cm, tube 6 mm, attached to the wall), its
  // side facing the camera beyond the wall
  const Segment handle_torus = torus({0.052, 0.0, 1.0}, {0, 0, 1}, 0.025, 0.006);
  handle = seen_handle(handle_torus, B, jitter);
  const auto tolerance = [](double) { return 0.006; };
  EXPECT_TRUE(features::tapered_wall(B, lower, upper, tolerance));
  EXPECT_FALSE(features::tapered_wall(B, lower, handle, tolerance));
  // a straight wall (no taper) with the handle: no line through the wall holds the handle
  std::vector<Eigen::Vector3d> straight;
  for (double a = -0.7; a <= 0.7; a += 0.05)
    for (double y = 0.045; y >= -0.045; y -= 0.004)
      straight.push_back(jitter({B.radius * std::sin(a), y, 1.0 - B.radius * std::cos(a)}));
  EXPECT_FALSE(features::tapered_wall(B, straight, handle, tolerance));
  // a handle's pixels (a third of its outer arc) with as many again of the wall about its roots (a
  // fat tube fitted to a D-shaped handle takes them: rendered stereo 4512, 54% of its points on
  // the wall): just over half lie on a line through the wall, yet a third stand beyond it, as no
  // tapered wall's do (the rule without that took it for one)
  std::vector<Eigen::Vector3d> rooted;
  for (std::size_t i = 0; i < handle.size(); i += 3) rooted.push_back(handle[i]);
  const std::size_t arc = rooted.size();
  for (std::size_t i = 0; rooted.size() < 2 * arc + 10; ++i) {
    const double a = 0.45 + 0.25 * double(i % 6) / 5, y = -0.03 + 0.06 * double((i / 6) % 13) / 12;
    rooted.push_back(jitter({B.radius * std::sin(a), y, 1.0 - B.radius * std::cos(a)}));
  }
  std::vector<Eigen::Vector3d> body_wall;  // (the body's own pixels outnumber the torus's 4 to 1)
  for (double a = -0.7; a <= 0.7; a += 0.035)
    for (double y = 0.045; y >= -0.045; y -= 0.002)
      body_wall.push_back(jitter({B.radius * std::sin(a), y, 1.0 - B.radius * std::cos(a)}));
  EXPECT_FALSE(features::tapered_wall(B, body_wall, rooted, tolerance));
  // a wall that would have to flare by 40 degrees to reach the points is no cup's
  std::vector<Eigen::Vector3d> flare;
  for (double a = -0.7; a <= 0.7; a += 0.05)
    for (double y = -0.004; y >= -0.045; y -= 0.004) {
      const double r = B.radius + std::tan(40 * M_PI / 180) * (-y);
      flare.push_back(jitter({r * std::sin(a), y, 1.0 - r * std::cos(a)}));
    }
  EXPECT_FALSE(features::tapered_wall(B, lower, flare, tolerance));
}

// Tapered cups (cone bodies, 4-10 degrees) in the renderer with its Kinect-like noise, found as
// cones by the detector (classes plane, cylinder, cone; points above the table): the cone's radii
// at the true ends of the body within 2 mm and its axis within 2 degrees; upright cylinders
// stay cylinders (bodies of at least 700 pixels). The detector's rule that tries a cylinder as a
// cone was set on seeds 1100-1123 (27 of 30 cups found); these are seeds 1124-1147, held out.
// A cone must taper by 5 degrees (Cone::min_departure): the renderer's cups taper by 4-10, and
// those of 6 or more must be cones.
TEST(Features, TaperedCupsAreConesWithTheirRadiiAndAxis) {
  synthetic::SceneOptions so;
  so.tapered_cups = true;
  std::vector<double> radius_mm, axis_deg;
  int cups = 0, found = 0, upright = 0, upright_as_cones = 0, steep = 0, steep_found = 0;
  for (std::uint64_t seed = 1124; seed < 1148; ++seed) {
    const auto sf = synthetic::render(seed, so);
    const Cloud cloud = extension::back_project(sf.frame);
    const NormalMap normals = extension::estimate_normals(cloud);
    features::DetectOptions o;
    o.classes = {PrimitiveClass::of<shapes::Plane>(), PrimitiveClass::of<shapes::Cylinder>(),
                 PrimitiveClass::of<shapes::Cone>()};
    o.roi = extension::find_support_plane(cloud, normals).roi;
    o.focal_px = sf.frame.intrinsics.fx;
    const auto segs = features::detect_primitives(cloud, normals, o);
    for (const auto& obj : sf.truth.objects_truth) {
      const auto* body = obj.part("body");
      if (!body || body->visible_pixels < 700) continue;
      if (obj.model == "mug" || obj.model == "jar" || obj.model == "can") {
        ++upright;
        for (const auto& s : segs)
          if (!s.inward && bench::majority_label(s, sf.truth.parts).first == body->label && s.is<shapes::Cone>()) {
            ++upright_as_cones;
            break;
          }
      }
      if (obj.model != "tapered_cup") continue;
      ++cups;
      const synthetic::Shape& t = body->camera;
      const bool is_steep = t.angle >= 6 * M_PI / 180;
      steep += is_steep;
      const Segment* best = nullptr;
      for (const auto& s : segs)
        if (s.is<shapes::Cone>() && !s.inward && bench::majority_label(s, sf.truth.parts).first == body->label &&
            (!best || s.inliers > best->inliers))
          best = &s;
      if (!best) continue;
      ++found;
      steep_found += is_steep;
      const auto& c = best->as<shapes::Cone>();
      double worst = 0;
      for (double end : {-0.5, 0.5}) {
        const Eigen::Vector3d at = t.point + t.axis * (end * t.height);
        const double truth = t.radius + std::tan(t.angle) * end * t.height;
        worst = std::max(worst, std::abs(c.radius_at(c.axis.normalized().dot(at - c.point)) - truth));
      }
      radius_mm.push_back(1000 * worst);
      axis_deg.push_back(std::acos(std::min(1.0, std::abs(c.axis.normalized().dot(t.axis.normalized())))) * 180 / M_PI);
    }
  }
  ASSERT_GE(cups, 10);
  std::sort(radius_mm.begin(), radius_mm.end()), std::sort(axis_deg.begin(), axis_deg.end());
  std::printf("tapered cups: %d of %d found as cones (%d of %d tapering by 6 degrees or more); radius error at the "
              "ends: median %.2f mm, max %.2f mm; axis: median %.2f deg, max %.2f deg\n", found, cups, steep_found, steep,
              bench::median(radius_mm),
              radius_mm.empty() ? NAN : radius_mm.back(), bench::median(axis_deg), axis_deg.empty() ? NAN : axis_deg.back());
  std::printf("upright cylinders (mugs, jars, cans) taken for cones: %d of %d\n", upright_as_cones, upright);
  ASSERT_GE(steep, 8);
  EXPECT_GE(steep_found, int(0.9 * steep));
  EXPECT_LE(upright_as_cones, int(0.1 * upright));
  for (double e : radius_mm) EXPECT_LE(e, 2.0);
  for (double e : axis_deg) EXPECT_LE(e, 2.0);
}

namespace {
/// What a camera in front sees of the upright box [-w/2, w/2] x [-t/2, t/2] x [0, h] (world, z up
/// from the support) and, when cap_h > 0, of a cap of side cap_w on top up to h + cap_h: the
/// front faces (y = -t/2, -cap_w/2) and the top faces, on a 2 mm grid. The support is z = 0 and
/// the camera frame is the world shifted 1 m (only the points matter here).
struct BoxCloud {
  Cloud cloud;
  extension::SupportPlane plane;
  std::vector<int> pixels;
};
BoxCloud box_cloud(double w, double t, double h, double cap_w, double cap_h) {
  std::vector<Eigen::Vector3d> pts;
  const double step = 0.002;
  const auto face = [&](double x0, double x1, double y0, double y1, double z0, double z1) {
    for (double x = x0 + step / 2; x < x1; x += step)
      for (double y = y0; y <= y1; y += step)
        for (double z = z0; z <= z1; z += step) pts.emplace_back(x, y, z);
  };
  face(-w / 2, w / 2, -t / 2, -t / 2, step / 2, h);   // front
  face(-w / 2, w / 2, -t / 2 + step, t / 2, h, h);    // top
  if (cap_h > 0) {
    face(-cap_w / 2, cap_w / 2, -cap_w / 2, -cap_w / 2, h + step, h + cap_h);  // the cap's front
    face(-cap_w / 2, cap_w / 2, -cap_w / 2 + step, cap_w / 2, h + cap_h, h + cap_h);
  }
  BoxCloud b;
  b.cloud = Cloud(1, int(pts.size()), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    float* p = b.cloud.ptr(0, int(i));
    p[0] = float(pts[i].x()), p[1] = float(pts[i].y()), p[2] = float(pts[i].z() + 1.0);  // camera frame
    b.pixels.push_back(int(i));
  }
  b.plane.normal = Eigen::Vector3d::UnitZ();
  b.plane.d = -1.0;
  b.plane.world_from_camera = Pose(Eigen::Translation3d(0, 0, -1.0));
  return b;
}
}  // namespace

TEST(Regions, AnUprightBoxAndABottleWithACapAreMeasuredAsTheyAre) {
  // a box 12 x 6 x 15 cm: as wide, thick and tall as it is, standing on the support, no neck
  const BoxCloud box = box_cloud(0.12, 0.06, 0.15, 0, 0);
  const auto r = features::describe_region(box.cloud, box.plane, box.pixels);
  ASSERT_TRUE(r.has_value());
  ASSERT_TRUE(r->is<shapes::Region>());
  const auto& g = r->as<shapes::Region>();
  EXPECT_NEAR(g.width, 0.12, 0.006);  // (the 2nd to 98th percentile of the points)
  EXPECT_NEAR(g.thickness, 0.06, 0.01);  // (seen on its top face only: fewer points, a wider trim)
  EXPECT_NEAR(g.height, 0.15, 0.004);
  EXPECT_NEAR(g.foot, 0.0, 0.005);
  EXPECT_GT(g.neck, 0.9);
  EXPECT_NEAR(std::abs(g.width_axis.x()), 1.0, 1e-6);  // the width is along x
  EXPECT_NEAR(g.point.z(), 1.0 + 0.075, 0.003);        // the box's middle, camera frame
  EXPECT_EQ(r->pixels.size(), box.pixels.size());
  EXPECT_NEAR(*r->attribute("slenderness"), g.height / g.width, 1e-9);
  // the solid box: inside 0, beside it the distance to its side
  EXPECT_DOUBLE_EQ(g.surface_distance(g.point), 0.0);
  EXPECT_NEAR(g.surface_distance(g.point + Eigen::Vector3d(g.width / 2 + 0.05, 0, 0)), 0.05, 1e-9);
  EXPECT_NEAR(g.half_extent_along(Eigen::Vector3d::UnitZ()), g.height / 2, 1e-9);

  // a bottle: a body 8 x 5 x 17 cm and a cap 2 cm across, 5 cm tall: the top sixth is the cap
  const BoxCloud bottle = box_cloud(0.08, 0.05, 0.17, 0.02, 0.05);
  const auto b = features::describe_region(bottle.cloud, bottle.plane, bottle.pixels);
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->as<shapes::Region>().height, 0.22, 0.006);
  EXPECT_LT(b->as<shapes::Region>().neck, 0.35);

  // a flat thing lower than min_height is no region
  const BoxCloud card = box_cloud(0.1, 0.06, 0.01, 0, 0);
  EXPECT_FALSE(features::describe_region(card.cloud, card.plane, card.pixels).has_value());
}

TEST(Regions, ARegionGoesThroughJsonFieldsAndBack) {
  shapes::Region g;
  g.point = {0.1, -0.2, 0.9}, g.axis = {0, -1, 0}, g.width_axis = {1, 0, 0};
  g.width = 0.08, g.thickness = 0.05, g.height = 0.2, g.foot = 0.01, g.neck = 0.3;
  Segment s(g);
  Segment t(PrimitiveClass::of<shapes::Region>().make());
  for (const auto& [name, value] : s.fields()) ASSERT_TRUE(t.set_field(name, value)) << name;
  for (const char* a : shapes::Region::attributes) EXPECT_EQ(*t.attribute(a), *s.attribute(a)) << a;
  EXPECT_STREQ(t.class_name(), "region");
}

TEST(Features, ABodyThatBendsAlongItsAxisShowsItInItsNormalsAndACylinderDoesNot) {
  // 1 m in front of the camera: a tube of radius 2 cm bent on a ring of radius 20 cm (a banana),
  // seen over 30 degrees of the ring (image rows) and 120 degrees of the tube (columns); and a
  // straight cylinder of the same radius. Both are taken as the same cylinder segment. Their
  // normals exact, then with the noise of a stereo camera: tilted along the axis by a random
  // angle (0.15 rad) shared by each 5 x 5 pixel patch.
  const double R = 0.2, r = 0.02;
  const Eigen::Vector3d centre(0, 0, 1), ring_normal = Eigen::Vector3d::UnitY();
  const auto sample = [&](bool bent, bool noisy, Cloud& cloud, NormalMap& normals) {
    const int rows = 61, cols = 61;
    cloud = Cloud(rows, cols);
    normals = NormalMap(rows, cols);
    std::mt19937 rng(7);
    std::normal_distribution<double> tilt(0.0, 0.15);
    std::vector<double> patch(13 * 13);
    for (double& x : patch) x = noisy ? tilt(rng) : 0.0;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const double f = (-15 + 0.5 * i) * M_PI / 180, t = (-60 + 2 * j) * M_PI / 180;
        // the tube's centre line runs along x; its cross-section faces the camera (-z)
        const Eigen::Vector3d radial = bent ? Eigen::Vector3d(std::sin(f), 0, -std::cos(f)) : Eigen::Vector3d(0, 0, -1);
        const Eigen::Vector3d along = bent ? Eigen::Vector3d(std::sin(f) * (R + r), 0, 0) : Eigen::Vector3d(f * (R + r), 0, 0);
        const Eigen::Vector3d n = std::cos(t) * radial + std::sin(t) * ring_normal;
        const Eigen::Vector3d base = bent ? Eigen::Vector3d(centre + Eigen::Vector3d(0, 0, R) + R * radial)
                                          : Eigen::Vector3d(centre + along);
        const Eigen::Vector3d p = base + r * n;
        const Eigen::Vector3d seen = (n + patch[(i / 5) * 13 + j / 5] * Eigen::Vector3d::UnitX()).normalized();
        for (int k = 0; k < 3; ++k) cloud.ptr(i, j)[k] = float(p(k)), normals.ptr(i, j)[k] = float(seen(k));
      }
  };
  // the bend reported: the RMS over the pixels of the slope along the axis of the normals'
  // component along it, cos(azimuth) / (R + r) on the bent tube
  double cos2 = 0;
  for (int j = 0; j < 61; ++j) cos2 += std::pow(std::cos((-60 + 2 * j) * M_PI / 180), 2) / 61;
  const double expected = std::sqrt(cos2) / (R + r);
  const features::DetectOptions o;
  for (bool noisy : {false, true})
    for (bool bent : {false, true}) {
      Cloud cloud;
      NormalMap normals;
      sample(bent, noisy, cloud, normals);
      const fd::Pixels f(cloud, normals, o);
      Segment s = cylinder(centre, Eigen::Vector3d::UnitX(), r, 0.1);
      for (int i = 0; i < int(cloud.pixels()); ++i) s.pixels.push_back(i);
      fd::measure_bend(f, s);
      if (bent)
        EXPECT_NEAR(s.bend, expected, noisy ? 0.8 : 0.2) << "1 / m, noisy " << noisy;
      else
        EXPECT_NEAR(s.bend, 0.0, 1e-6) << "noisy " << noisy;
    }
}

TEST(Features, ARoundedBoxFittedByACylinderIsOutOfRoundAndACylinderIsNot) {
  // 0.8 m in front of the camera, lying across the view (axis along x): a box 6.5 x 7.7 cm across
  // with edges rounded to 2.3 cm (rendered 5004's soap box, taken for a lying can), and a round
  // cylinder of 3.5 cm; their sides facing the camera, 61 rows along the axis and 81 columns
  // around it. Each is fitted by a cylinder (least squares) whose inliers, within 5 mm, are the
  // segment, as the search leaves it. Exact, then with a Kinect-like noise along the rays
  // (1.5 mm), then a stereo-like one (3 mm shared by each 5 x 5 pixel patch, 1 mm per pixel).
  // Measured: the box 0.041, 0.040 and 0.033 of the radius; the cylinder 0 (no pattern beyond noise).
  const Eigen::Vector3d centre(0, 0, 0.8);
  // the rounded rectangle (half sizes a, b, edges rounded to rc) as the points within rc of its
  // inner rectangle; rc = a = b is a circle
  const auto boundary = [](double a, double b, double rc, double phi) {  // phi: from -z towards +y
    const Eigen::Vector2d u(std::sin(phi), -std::cos(phi));               // (y, z)
    const auto outside = [&](double t) {
      const Eigen::Vector2d p = t * u, q(std::clamp(p.x(), -(a - rc), a - rc), std::clamp(p.y(), -(b - rc), b - rc));
      return (p - q).norm() > rc;
    };
    double lo = 0, hi = 1;
    for (int k = 0; k < 60; ++k) (outside(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    return Eigen::Vector2d(lo * u);
  };
  const auto out_of_round = [&](double a, double b, double rc, int noise) {
    const int rows = 61, cols = 81;
    Cloud cloud(rows, cols);
    NormalMap normals(rows, cols);
    std::mt19937 rng(11);
    std::normal_distribution<double> unit(0.0, 1.0);
    std::vector<double> patch(13 * 17);
    for (double& x : patch) x = noise == 2 ? 0.003 * unit(rng) : 0.0;
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const Eigen::Vector2d yz = boundary(a, b, rc, (-80 + 2 * j) * M_PI / 180);
        Eigen::Vector3d p = centre + Eigen::Vector3d(-0.05 + 0.1 * i / (rows - 1), yz.x(), yz.y());
        const double along = noise == 1 ? 0.0015 * unit(rng) : noise == 2 ? patch[(i / 5) * 17 + j / 5] + 0.001 * unit(rng) : 0.0;
        p += along * p.normalized();
        const Eigen::Vector3d n(0, yz.x(), yz.y());
        for (int k = 0; k < 3; ++k) cloud.ptr(i, j)[k] = float(p(k)), normals.ptr(i, j)[k] = float(n.normalized()(k));
        pts.push_back(p);
      }
    const features::DetectOptions o;
    const fd::Pixels f(cloud, normals, o);
    const Segment fitted = fd::refit_points(cylinder(centre, Eigen::Vector3d::UnitX(), std::max(a, b)), pts);
    Segment s = cylinder(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 0);
    s.shape = fitted.shape;
    for (int i = 0; i < int(cloud.pixels()); ++i)
      if (std::abs(s.signed_distance(pts[std::size_t(i)])) < 0.005) s.pixels.push_back(i);
    EXPECT_GT(s.pixels.size(), cloud.pixels() / 2);
    fd::measure_out_of_round(f, s);
    return s.out_of_round;
  };
  for (int noise : {0, 1, 2}) {
    EXPECT_EQ(out_of_round(0.035, 0.035, 0.035, noise), 0.0) << "a round cylinder, noise " << noise;
    // the exact box: 0.041 of the radius; the models' containers take at most 0.02 to 0.03
    EXPECT_GT(out_of_round(0.0325, 0.0385, 0.023, noise), noise == 2 ? 0.025 : 0.035) << "the rounded box, noise " << noise;
  }
}

TEST(Features, ASphereKnowsWhereOnItItWasSeen) {
  // the cap: the mean unit direction from the centre to the points; a bowl's outer wall (below
  // the centre, up = -y in the camera frame here) and a dome (above it) point opposite ways
  shapes::Sphere bowl{Eigen::Vector3d(0, 0, 1), 0.06}, dome = bowl;
  std::vector<Eigen::Vector3d> below, above;
  for (double a = 0; a < 2 * M_PI; a += 0.1)
    for (double e = 0.05; e < M_PI / 2; e += 0.05) {
      const Eigen::Vector3d d(std::cos(a) * std::cos(e), std::sin(e), std::sin(a) * std::cos(e));  // +y: down
      below.push_back(bowl.center + bowl.radius * d);
      above.push_back(bowl.center + bowl.radius * Eigen::Vector3d(d.x(), -d.y(), d.z()));
    }
  bowl.set_extent(below), dome.set_extent(above);
  const Eigen::Vector3d up = -Eigen::Vector3d::UnitY();
  // points evenly spaced in elevation: the mean of sin(elevation) over (0, 90 degrees) is 2 / pi
  EXPECT_NEAR(bowl.cap.dot(up), -2 / M_PI, 0.02);
  EXPECT_NEAR(dome.cap.dot(up), 2 / M_PI, 0.02);
  EXPECT_NEAR(bowl.cap.x(), 0.0, 1e-2);
  // moved with the sphere
  Segment s(bowl);
  const Eigen::Isometry3d T(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(s.transformed(T).as<shapes::Sphere>().cap.dot(-up), -2 / M_PI, 0.02);
}

// A rendered frame with the renderer's active-stereo depth, taken through the tabletop graph's
// steps up to the primitives (3x3 depth filter, fast normals, support plane, the region above it,
// curved shapes measured on the unfiltered points): the detector's inputs and options.
struct StereoTabletop {
  synthetic::SyntheticFrame sf;
  Cloud cloud;
  NormalMap normals;
  features::DetectOptions o;
};
StereoTabletop stereo_tabletop(synthetic::SyntheticFrame sf) {
  signal::DepthFilterOptions fo;
  fo.radius = 1;
  StereoTabletop t{std::move(sf), {}, {}, {}};
  t.cloud = extension::back_project(signal::filter_depth(t.sf.frame, fo));
  t.normals = extension::estimate_normals(t.cloud);
  const auto table = extension::find_support_plane(t.cloud, t.normals);
  t.o.roi = table.roi;
  t.o.unfiltered = extension::back_project(t.sf.frame);
  t.o.support << table.normal, table.d;
  t.o.focal_px = t.sf.frame.intrinsics.fx;
  return t;
}
StereoTabletop stereo_tabletop(std::uint64_t seed, synthetic::SceneOptions so = {}) {
  so.depth_model = synthetic::DepthModel::Stereo;
  return stereo_tabletop(synthetic::render(seed, so));
}

// Upright bodies without normals (features/upright.cpp): with the renderer's active-stereo depth
// (wavy at a metre: errors of ~9 mm correlated over ~9 pixels) the normals of a mug or a can turn
// too far for the bottom-up search, which misses many bodies; given the support's normal, the
// upright search finds them as circles in the support plane, with their true radii. The steps are
// the tabletop graph's (3x3 depth filter, fast normals, support plane, the region above it, bodies
// measured on the unfiltered points). Seeds 940-951 were used for nothing else. The figures pool
// two RANSAC seeds: one alone moves false cylinders per frame between 0.25 and 1.17 (seeds 0-7).
TEST(Features, UprightBodiesAreFoundInWavyStereoDepthWithoutNormals) {
  bench::SyntheticScore bottom_up, upright;
  for (std::uint64_t seed = 940; seed < 952; ++seed) {
    auto t = stereo_tabletop(seed);
    t.o.classes = {PrimitiveClass::of<shapes::Plane>(), PrimitiveClass::of<shapes::Cylinder>(),
                   PrimitiveClass::of<shapes::Cone>(), PrimitiveClass::of<shapes::Sphere>()};
    for (const int ransac_seed : {0, 1})
      for (const bool on : {false, true}) {
        t.o.seed = ransac_seed, t.o.upright_bodies = on;
        bench::score_synthetic(t.sf.truth, features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color),
                               on ? "upright" : "bottom-up", on ? upright : bottom_up);
      }
  }
  const std::string figures = "body recall: bottom-up " + std::to_string(bottom_up.body_recall()) + ", with the upright search " +
                              std::to_string(upright.body_recall()) + " of " + std::to_string(upright.bodies) +
                              "; median radius error " + std::to_string(bench::median(upright.radius_err_mm)) + " mm";
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(upright.bodies, 50);
  EXPECT_GE(upright.body_recall(), bottom_up.body_recall() + 0.1);
  EXPECT_LT(bench::median(upright.radius_err_mm), 3.0);
  EXPECT_LT(upright.false_cylinders_per_frame(), 1.0);
}

// Upright bodies held upright (features/upright.cpp, hold_upright): in wavy stereo depth a free
// fit of a standing body's wall leans by a few degrees; a body found bottom-up within 20 degrees of
// the support's normal is refitted with its axis along the normal (a cylinder, or a cone where one
// fits clearly better) and kept so when that fits about as well. Stereo seeds 1400-1429 (used for
// nothing else), tapered cups and lying cans in the scenes, bodies with at least 700 pixels.
// Without the hold: axis error median 0.95 deg, 90th percentile 5.6 deg; tapered cups as cones 13
// of 21; upright mugs, jars and cans as cones 3 of 66. With it a few jars held upright taper (8 of
// 67 when written; the jar model's lid and closed end tell them from cups).
TEST(Features, StandingBodiesInWavyStereoDepthAreHeldUprightAndTaperedCupsStayCones) {
  synthetic::SceneOptions so;
  so.tapered_cups = true;
  so.lying_containers = true;
  int upright = 0, as_cones = 0, cups = 0, cups_as_cones = 0;
  std::vector<double> axis_deg;  // of the upright bodies' segments
  for (std::uint64_t seed = 1400; seed < 1430; ++seed) {
    auto t = stereo_tabletop(seed, so);
    t.o.classes = {PrimitiveClass::of<shapes::Plane>(), PrimitiveClass::of<shapes::Cylinder>(),
                   PrimitiveClass::of<shapes::Cone>(), PrimitiveClass::of<shapes::Sphere>()};
    t.o.upright_bodies = true;
    const auto segs = features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color);
    // the class of the largest outward segment mostly on a body
    const auto found = [&](const synthetic::PartTruth& body) -> const Segment* {
      const Segment* best = nullptr;
      for (const auto& s : segs)
        if (!s.inward && (s.is<shapes::Cylinder>() || s.is<shapes::Cone>()) &&
            bench::majority_label(s, t.sf.truth.parts).first == body.label && (!best || s.inliers > best->inliers))
          best = &s;
      return best;
    };
    for (const auto& obj : t.sf.truth.objects_truth) {
      const auto* body = obj.part("body");
      if (!body || body->visible_pixels < 700) continue;
      const Segment* s = found(*body);
      if (!s) continue;
      if (obj.model == "tapered_cup") {
        ++cups, cups_as_cones += s->is<shapes::Cone>();
      } else if ((obj.model == "mug" || obj.model == "jar" || obj.model == "can") && obj.pose != "lying") {
        ++upright, as_cones += s->is<shapes::Cone>();
        const double c = std::abs(s->direction()->normalized().dot(body->camera.axis.normalized()));
        axis_deg.push_back(std::acos(std::min(1.0, c)) * 180 / M_PI);
      }
    }
  }
  const std::string figures = "upright mugs, jars and cans found as cones: " + std::to_string(as_cones) + " of " +
                              std::to_string(upright) + "; tapered cups found as cones: " + std::to_string(cups_as_cones) +
                              " of " + std::to_string(cups) + "; upright bodies' axis error: median " +
                              std::to_string(bench::median(axis_deg)) + " deg, 90th percentile " +
                              std::to_string(bench::quantile(axis_deg, 0.9)) + " deg";
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(upright, 50);
  ASSERT_GE(cups, 15);
  EXPECT_LE(as_cones, int(0.15 * upright));
  EXPECT_GE(cups_as_cones, int(0.8 * cups));
  EXPECT_LT(bench::median(axis_deg), 0.8);         // (0.61 when written)
  EXPECT_LT(bench::quantile(axis_deg, 0.9), 3.5);  // (2.25)
}

// Handles from the colour image (detail::colour_handle): with the renderer's active-stereo depth a
// handle's tube beyond a metre loses its depth or is fattened into the table, and the depth search
// finds no ring; its silhouette beside the body, in the body's colour, is there. On rendered stereo
// frames (seeds 960-989, used for nothing else) the detector finds more of the handles with the
// colour image than without (at least half of a torus's pixels on a handle: bench::score_synthetic,
// handles within 1.5 m), and hardly more tori elsewhere.
TEST(Features, HandlesBesideTheBodyAreFoundInTheColourImageWhereDepthLosesThem) {
  bench::SyntheticScore depth_only, with_colour;
  for (std::uint64_t seed = 960; seed < 990; ++seed) {
    auto t = stereo_tabletop(seed);
    t.o.handle.from_edges = false;  // (the silhouette alone)
    for (const bool on : {false, true}) {
      t.o.handle.from_colour = on;
      bench::score_synthetic(t.sf.truth, features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color),
                             on ? "colour" : "depth", on ? with_colour : depth_only, 500, 150, 1.5);
    }
  }
  const std::string figures = "handle recall: depth only " + std::to_string(depth_only.handle_recall()) + ", with colour " +
                              std::to_string(with_colour.handle_recall()) + " of " + std::to_string(with_colour.handles) +
                              "; false tori " + std::to_string(depth_only.false_tori) + " -> " +
                              std::to_string(with_colour.false_tori) + " in 30 frames";
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(with_colour.handles, 15);
  EXPECT_GT(with_colour.handles_found, depth_only.handles_found);  // (0.68 -> 0.73 when written; 0.78 -> 0.92
                                                                   // once an implausible ring no longer hid it)
  EXPECT_LE(with_colour.false_tori, depth_only.false_tori + 1);
}

// Handles from the colour image's edges (detail::edge_handle), the edge modality on its own: with
// the silhouette search off, the detector finds more handles of far stereo mugs with the edges than
// from the depth alone, and hardly more tori elsewhere. Seeds 1500-1539 (used for nothing else).
TEST(Features, HandlesBesideTheBodyAreFoundAmongTheEdgesWhereDepthLosesThem) {
  bench::SyntheticScore depth_only, with_edges;
  for (std::uint64_t seed = 1500; seed < 1540; ++seed) {
    auto t = stereo_tabletop(seed);
    t.o.handle.from_colour = false;
    for (const bool on : {false, true}) {
      t.o.handle.from_edges = on;
      bench::score_synthetic(t.sf.truth, features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color),
                             on ? "edges" : "depth", on ? with_edges : depth_only, 500, 150, 1.5);
    }
  }
  const std::string figures = "handle recall: depth only " + std::to_string(depth_only.handle_recall()) + ", with edges " +
                              std::to_string(with_edges.handle_recall()) + " of " + std::to_string(with_edges.handles) +
                              "; false tori " + std::to_string(depth_only.false_tori) + " -> " +
                              std::to_string(with_edges.false_tori) + " in 40 frames";
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(with_edges.handles, 20);
  EXPECT_GT(with_edges.handles_found, depth_only.handles_found);
  EXPECT_LE(with_edges.false_tori, depth_only.false_tori + 1);
}

// The scene of `seed` with only its first mug on the table (and the room), the camera orbiting it at
// `distance` metres; none when the scene has no mug.
std::optional<synthetic::Scene> one_mug(std::uint64_t seed, const synthetic::SceneOptions& so, double distance) {
  synthetic::Scene scene = synthetic::generate_scene(seed, so);
  auto mug = std::find_if(scene.objects.begin(), scene.objects.end(), [](const auto& o) { return o.model == "mug"; });
  if (mug == scene.objects.end()) return std::nullopt;
  std::vector<synthetic::SceneObject> kept;
  for (const auto& o : scene.objects)
    if (o.model == "floor" || o.model == "wall" || o.model == "table" || &o == &*mug) kept.push_back(o);
  for (const auto& [role, shape] : mug->parts)
    if (role == "body") scene.look_at = shape.point;
  scene.objects = std::move(kept);
  scene.camera_distance = distance;
  return scene;
}

// Handles seen obliquely beyond a metre of stereo depth: the colour silhouette of a handle turned
// 20-60 degrees out of the limb's plane is looked for in planes turned about the body's axis
// (HandleOptions::colour_max_turn_deg) and not only in the limbs'. One mug alone on the table,
// the camera orbiting it at 1.4 m in 20 degree steps; seeds 1200-1209 (varied handles; those
// used for nothing else.
TEST(Features, ObliqueHandlesAreFoundInTheColourImageInTurnedPlanes) {
  synthetic::SceneOptions so;
  so.depth_model = synthetic::DepthModel::Stereo;
  so.handle_shapes = synthetic::HandleShapes::Varied;
  so.orbit_step_deg = 20;
  int oblique = 0, found_limbs = 0, found_turned = 0, false_limbs = 0, false_turned = 0;
  for (std::uint64_t seed = 1200; seed < 1210; ++seed) {
    const auto scene = one_mug(seed, so, 1.4);
    if (!scene) continue;  // (a scene without a mug)
    for (int k = 0; k < 18; ++k) {
      auto t = stereo_tabletop(synthetic::render(*scene, synthetic::orbit_view(*scene, k, so), so, k));
      const synthetic::PartTruth *body = nullptr, *handle = nullptr;
      for (const auto& o : t.sf.truth.objects_truth)
        for (const auto& p : o.parts)
          if (o.model == "mug" && p.role == "body") body = &p;
          else if (o.model == "mug" && p.role == "handle") handle = &p;
      ASSERT_TRUE(body && handle);
      if (body->visible_pixels < 500 || handle->visible_pixels < 150) continue;
      // the handle's angle out of the limb plane: 90 degrees less its angle to the camera about the axis
      const Eigen::Vector3d a = body->camera.axis.normalized(), p = body->camera.point;
      Eigen::Vector3d out = handle->camera.point - p, view = -p;
      out -= a * out.dot(a), view -= a * view.dot(a);
      const double turn = std::abs(90 - std::acos(out.normalized().dot(view.normalized())) * 180 / M_PI);
      if (turn < 20 || turn > 60) continue;
      ++oblique;
      for (const double max_turn : {0.0, 60.0}) {
        t.o.handle.colour_max_turn_deg = max_turn;
        bool found = false;
        int false_tori = 0;
        for (const Segment& s : features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color)) {
          if (!s.is<shapes::Torus>()) continue;
          const auto [label, purity] = bench::majority_label(s, t.sf.truth.parts);
          if (label == handle->label && purity >= 0.5) found = true;
          else ++false_tori;
        }
        (max_turn > 0 ? found_turned : found_limbs) += found;
        (max_turn > 0 ? false_turned : false_limbs) += false_tori;
      }
    }
  }
  const std::string figures = "oblique handles found: limbs' planes " + std::to_string(found_limbs) + ", turned planes " +
                              std::to_string(found_turned) + " of " + std::to_string(oblique) + "; false tori " +
                              std::to_string(false_limbs) + " -> " + std::to_string(false_turned);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(oblique, 12);
  EXPECT_GE(found_turned, found_limbs + 3);
  EXPECT_LE(false_turned, false_limbs + 1);
}

// A far body's wavy stereo wall may be fitted bottom-up, upright already, as a narrow strip of a
// much wider circle (a 33 mm strip of a 76 mm mug with a radius of 100 mm): the upright search
// then searches its pixels too, and the body replaces it. One mug at a time, orbited at 1.2 m
// (seeds 1300-1309, used for nothing else): upright cylinders on the body that span less than
// half their diameter across the view (when strips stayed: 7 in 162 views, 6 since the depth
// filter's vectorized kernel; 2 and 3 with the search), and the views whose body is found as an
// upright cylinder of its true radius (within 1 cm, centre within 1 cm: 122 -> 125 with the
// search, 119 either way since the new kernel, which moves these far stereo fits by chance).
// Each view is searched with two RANSAC seeds: over seeds 0-7 one seed alone leaves 1 to 6
// strips (mean 3), so a single seed's count says little.
TEST(Features, NarrowStripsOfWideCirclesGiveWayToTheUprightBody) {
  synthetic::SceneOptions so;
  so.depth_model = synthetic::DepthModel::Stereo;
  so.handle_shapes = synthetic::HandleShapes::Varied;
  so.orbit_step_deg = 20;
  int views = 0, found = 0, strips = 0;
  for (std::uint64_t seed = 1300; seed < 1310; ++seed) {
    const auto scene = one_mug(seed, so, 1.2);
    if (!scene) continue;  // (a scene without a mug)
    for (int k = 0; k < 18; ++k) {
      auto t = stereo_tabletop(synthetic::render(*scene, synthetic::orbit_view(*scene, k, so), so, k));
      const synthetic::PartTruth* body = nullptr;
      for (const auto& o : t.sf.truth.objects_truth)
        for (const auto& p : o.parts)
          if (o.model == "mug" && p.role == "body") body = &p;
      ASSERT_TRUE(body);
      if (body->visible_pixels < 500) continue;
      const Eigen::Vector3d a = body->camera.axis.normalized();
      for (const int ransac_seed : {0, 1}) {
        ++views;
        t.o.seed = ransac_seed;
        bool ok = false;
        for (const Segment& s : features::detect_primitives(t.cloud, t.normals, t.o, &t.sf.frame.color)) {
          const auto* c = s.get_if<shapes::Cylinder>();
          if (!c || s.inward || std::abs(c->axis.normalized().dot(a)) < 0.985) continue;
          if (bench::majority_label(s, t.sf.truth.parts).first != body->label) continue;
          // its pixels' width across the view, in the support plane
          const Eigen::Vector3d across = a.cross(c->point).normalized();
          std::vector<double> w;
          for (int i : s.pixels) {
            const float* q = t.o.unfiltered.ptr(i / t.o.unfiltered.cols(), i % t.o.unfiltered.cols());
            if (std::isfinite(q[2])) w.push_back(across.dot(Eigen::Vector3d(q[0], q[1], q[2])));
          }
          std::sort(w.begin(), w.end());
          if (w.size() >= 20 && w[w.size() * 98 / 100] - w[w.size() * 2 / 100] < c->radius) ++strips;
          Eigen::Vector3d off = c->point - body->camera.point;
          off -= a * off.dot(a);
          ok = ok || (off.norm() < 0.01 && std::abs(c->radius - body->camera.radius) < 0.01);
        }
        found += ok;
      }
    }
  }
  std::printf("bodies found with their radius: %d of %d views; narrow strips left on them: %d\n", found, views, strips);
  ASSERT_GE(views, 300);
  EXPECT_LE(strips, 8);
  EXPECT_GE(found, 230);
}

// Outer walls about an inside (detail::outer_walls): with the renderer's active-stereo depth a far
// mug's or cup's outer wall can escape the searches that do not know where its axis is, while its
// inside (the far wall seen through the rim) is found. Given exactly that inside (the renderer's
// inner wall: its shape and its pixels), the outer wall is looked for about its axis: on stereo
// seeds 1600-1639 (used for nothing else) it is found on most vessels, on the body's pixels, with
// the body's radius; the same inside moved 25 cm across the table (its pixels where they were)
// gives no wall: the wall must meet the inside at the rim.
TEST(Features, TheOuterWallOfAVesselIsFoundAboutItsInside) {
  int vessels = 0, found = 0, on_body = 0, on_table = 0;
  std::vector<double> radius_err_mm;
  for (std::uint64_t seed = 1600; seed < 1640; ++seed) {
    const auto t = stereo_tabletop(seed);
    const Eigen::Vector3d up = t.o.support.head<3>();
    for (const auto& obj : t.sf.truth.objects_truth) {
      const auto* body = obj.part("body");
      const auto* inside = obj.part("inside");
      if (!body || !inside || body->camera.cls != "cylinder" || inside->camera.cls != "cylinder" ||
          body->visible_pixels < 300 || inside->visible_pixels < 150)
        continue;
      auto inner = inside->camera.segment();
      ASSERT_TRUE(inner);
      for (std::size_t i = 0; i < t.sf.truth.parts.size(); ++i)
        if (t.sf.truth.parts.data()[i] == inside->label) inner->pixels.push_back(int(i));
      inner->inward = true;
      {
        fd::Pixels f(t.cloud, t.normals, t.o);
        std::vector<Segment> out{*inner};
        fd::outer_walls(f, t.o.support, out, 0.02, 0.15, &t.sf.frame.color);
        ++vessels;
        if (out.size() == 2) {
          ++found;
          const auto& wall = out[1].as<shapes::Cylinder>();
          on_body += bench::majority_label(out[1], t.sf.truth.parts).first == body->label;
          radius_err_mm.push_back(1000 * std::abs(wall.radius - body->camera.radius));
        }
      }
      // the same inside moved 25 cm across the table, away from the camera's line to it
      Segment moved = *inner;
      moved.as<shapes::Cylinder>().point += 0.25 * up.normalized().cross(inner->as<shapes::Cylinder>().point).normalized();
      fd::Pixels f(t.cloud, t.normals, t.o);
      std::vector<Segment> out{moved};
      fd::outer_walls(f, t.o.support, out, 0.02, 0.15, &t.sf.frame.color);
      on_table += out.size() == 2 && bench::majority_label(out[1], t.sf.truth.parts).first != body->label;
    }
  }
  const std::string figures = "outer walls found about " + std::to_string(found) + " of " + std::to_string(vessels) +
                              " insides, " + std::to_string(on_body) + " on the body; median radius error " +
                              std::to_string(bench::median(radius_err_mm)) + " mm; walls about moved insides: " +
                              std::to_string(on_table);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(vessels, 30);
  EXPECT_GE(found, int(0.8 * vessels));
  EXPECT_GE(on_body, int(0.95 * found));
  EXPECT_LT(bench::median(radius_err_mm), 3.0);
  EXPECT_LE(on_table, vessels / 20);
}

// Two bodies standing on the support cannot overlap (detail::search_upright): a circle that would
// overlap an upright body found before it is no body, unless it holds twice that body's pixels,
// and then it displaces it (the first found is not always the true one). On stereo seeds
// 1800-1819 (used for nothing else), each standing body that the search finds on its own is
// looked for again beside a wrong upright circle planted behind it (12 cm, overlapping it):
// with a quarter of the body's pixels the plant gives way, with twice them it stays and the body
// is not found.
TEST(Features, AStandingBodyDisplacesAWeakerUprightCircleItWouldOverlap) {
  synthetic::SceneOptions so;
  so.lying_containers = true;
  int bodies = 0, beside_weak = 0, weak_dropped = 0, beside_strong = 0;
  for (std::uint64_t seed = 1800; seed < 1820; ++seed) {
    const auto t = stereo_tabletop(seed, so);
    const Eigen::Vector3d up = t.o.support.head<3>().normalized();
    const auto flat = [&](Eigen::Vector3d v) { return Eigen::Vector3d(v - up * v.dot(up)); };
    for (const auto& obj : t.sf.truth.objects_truth) {
      const auto* body = obj.part("body");
      if (!body || body->camera.cls != "cylinder" || body->visible_pixels < 700 ||
          std::abs(body->camera.axis.normalized().dot(up)) < 0.985)
        continue;
      const auto found = [&](const std::vector<Segment>& out) {
        for (const auto& s : out) {
          const auto* c = s.get_if<shapes::Cylinder>();
          if (c && !s.inward && std::abs(c->radius - body->camera.radius) < 0.01 &&
              flat(c->point - body->camera.point).norm() < 0.01)
            return true;
        }
        return false;
      };
      const auto search = [&](std::vector<Segment> out) {
        fd::Pixels f(t.cloud, t.normals, t.o);
        fd::search_upright(f, t.o.support, out, t.o.min_support, 0.02, 0.15, 20, &t.sf.frame.color);
        return out;
      };
      if (!found(search({}))) continue;
      ++bodies;
      // the plant: upright, 12 cm, its centre 13 cm behind the body's; its pixels a run of the
      // frame's from the bottom row up, 30 cm or more from the body (they only count)
      shapes::Cylinder wrong;
      wrong.axis = up, wrong.radius = 0.12, wrong.height = 0.1;
      wrong.point = body->camera.point + 0.13 * flat(body->camera.point).normalized();
      const auto plant = [&](std::size_t n) {
        Segment s{wrong};
        for (int i = int(t.cloud.rows() * t.cloud.cols()) - 1; i >= 0 && s.pixels.size() < n; --i) {
          const float* q = t.cloud.data() + 3 * std::size_t(i);
          if (std::isfinite(q[2]) && (Eigen::Vector3d(q[0], q[1], q[2]) - body->camera.point).norm() > 0.3)
            s.pixels.push_back(i);
        }
        s.inliers = s.pixels.size();
        return s;
      };
      const auto weak = search({plant(body->visible_pixels / 4)});
      beside_weak += found(weak);
      weak_dropped += found(weak) && std::none_of(weak.begin(), weak.end(), [](const Segment& s) {
                        const auto* c = s.get_if<shapes::Cylinder>();
                        return c && c->radius == 0.12;
                      });
      beside_strong += found(search({plant(2 * body->visible_pixels)}));
    }
  }
  std::printf("standing bodies found: %d; beside a weaker overlapping circle %d (it dropped: %d), beside a stronger %d\n",
              bodies, beside_weak, weak_dropped, beside_strong);
  ASSERT_GE(bodies, 20);
  EXPECT_GE(beside_weak, 0.9 * bodies);
  EXPECT_EQ(weak_dropped, beside_weak);
  EXPECT_EQ(beside_strong, 0);
}

// A standing body behind another (features/upright.cpp, foot_hidden): the lowest pixels of its
// wall end well above the support, yet it stands on it, for its foot is hidden by something in
// front; a body on a box, whose surface goes on from its foot down to the table (as a drill's grip
// into its battery), and a body in full view have no hidden foot. One mug alone on the table
// (seeds 1840-1851, used for nothing else), seen from two sides at 1.1 m with stereo depth: as it
// is, behind a tin 2 cm in front of its wall that hides its lower 60% from the camera, and lifted
// onto a 6 cm box; the function is asked about the wall's true pixels (the renderer's labels)
// whose depth lies on the wall.
TEST(Features, ABodyBehindAnotherHasItsFootHidden) {
  synthetic::SceneOptions so;
  so.depth_model = synthetic::DepthModel::Stereo;
  so.orbit_step_deg = 150;
  int views = 0, in_view_hidden = 0, behind_hidden = 0, lifted_hidden = 0;
  std::vector<double> behind_feet;
  for (std::uint64_t seed = 1840; seed < 1852; ++seed) {
    const auto scene = one_mug(seed, so, 1.1);
    if (!scene) continue;  // (a scene without a mug)
    for (int k = 0; k < 2; ++k) {
      const Pose view = synthetic::orbit_view(*scene, k, so);
      const synthetic::SceneObject& mug = *std::find_if(scene->objects.begin(), scene->objects.end(),
                                                        [](const auto& o) { return o.model == "mug"; });
      const synthetic::Shape* body_world = nullptr;
      for (const auto& [role, shape] : mug.parts)
        if (role == "body") body_world = &shape;
      ASSERT_TRUE(body_world);
      const double r = body_world->radius, h = body_world->height;
      const Eigen::Vector3d foot = body_world->point - Eigen::Vector3d::UnitZ() * (0.5 * h);
      Eigen::Vector3d toward = view.translation() - foot;
      const double down = toward.z() / std::hypot(toward.x(), toward.y());  // the view's slope
      toward.z() = 0;
      toward.normalize();
      // a tin 2 cm in front of the wall, tall enough to hide the wall's lower 60% from the camera
      constexpr double kTin = 0.055;  // (wider than the mug: none of its foot shows beside it)
      const double tall = 0.6 * h + 0.02 * down;
      synthetic::SceneObject tin;
      tin.model = "jar";
      synthetic::Shape side, lid;
      side.cls = "cylinder", side.point = foot + toward * (r + 0.02 + kTin) + Eigen::Vector3d::UnitZ() * (0.5 * tall);
      side.radius = kTin, side.height = tall;
      lid.cls = "disc", lid.point = side.point + Eigen::Vector3d::UnitZ() * (0.5 * tall), lid.radius = kTin;
      tin.parts = {{"body", side}, {"lid", lid}};
      tin.color = Eigen::Vector3f(0.7f, 0.6f, 0.2f);
      synthetic::Scene behind = *scene, on_box = *scene;
      behind.objects.push_back(tin);
      // the mug on a box 6 cm tall, 2 cm wider than it each way
      Pose lift = Pose::Identity();
      lift.translation() = Eigen::Vector3d(0, 0, 0.06);
      for (auto& o : on_box.objects)
        if (o.model == "mug")
          for (auto& [role, shape] : o.parts) shape = shape.transformed(lift);
      synthetic::SceneObject box;
      box.model = "box";
      synthetic::Shape b;
      b.cls = "box", b.point = foot + Eigen::Vector3d::UnitZ() * 0.03, b.axis2 = toward;
      b.size = Eigen::Vector3d(2 * r + 0.04, 2 * r + 0.04, 0.06);
      box.parts = {{"body", b}};
      on_box.objects.push_back(box);
      // foot_hidden of the wall's true pixels, and the height of their 5th percentile (the foot
      // search_upright measures)
      const auto hidden = [&](const synthetic::Scene& sc, double* foot_height) {
        auto t = stereo_tabletop(synthetic::render(sc, view, so, k));
        const synthetic::PartTruth* body = nullptr;
        for (const auto& o : t.sf.truth.objects_truth)
          if (o.model == "mug") body = o.part("body");
        EXPECT_TRUE(body);
        if (!body) return false;
        fd::Pixels f(t.cloud, t.normals, t.o);
        const Eigen::Vector3d n = t.o.support.head<3>();
        std::vector<int> pix;
        std::vector<double> heights;
        const auto wall = body->camera.segment();  // (its pixels whose depth lies on it: a stereo
        EXPECT_TRUE(wall);                           // match smears the tin's over its edge)
        if (!wall) return false;
        for (int i = 0; i < f.H * f.W; ++i)
          if (t.sf.truth.parts.data()[i] == body->label && f.p(i).allFinite() &&
              std::abs(wall->signed_distance(f.p(i))) <= f.eps(f.p(i).z()))
            pix.push_back(i), heights.push_back((n.dot(f.p(i)) + t.o.support(3)) / n.norm());
        if (pix.size() < 50) return false;
        std::nth_element(heights.begin(), heights.begin() + std::ptrdiff_t(heights.size() / 20), heights.end());
        const double q = heights[heights.size() / 20];
        if (foot_height) *foot_height = q;
        return fd::foot_hidden(f, t.o.support, pix, q);
      };
      ++views;
      in_view_hidden += hidden(*scene, nullptr);
      double q = 0;
      behind_hidden += hidden(behind, &q);
      behind_feet.push_back(q);
      lifted_hidden += hidden(on_box, nullptr);
    }
  }
  const std::string figures = std::to_string(views) + " views of a mug; its foot hidden: in full view " +
                              std::to_string(in_view_hidden) + ", behind a tin " + std::to_string(behind_hidden) +
                              " (its wall's foot seen " + std::to_string(bench::median(behind_feet)) +
                              " m up, median), on a box " + std::to_string(lifted_hidden);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  ASSERT_GE(views, 16);
  EXPECT_EQ(in_view_hidden, 0);
  EXPECT_GE(behind_hidden, 0.9 * views);
  EXPECT_EQ(lifted_hidden, 0);
}

// The refits' closed-form gradient of the range residual (the Jacobian of their Levenberg-
// Marquardt) against central differences of the residual itself, over pack()'s parameters with
// an axis of any length: cylinders seen from outside and inside (near and far crossings), rays
// that graze or miss (the geometric fallback), and spheres.
TEST(Features, TheRangeResidualsGradientMatchesItsDifferences) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  int checked = 0;
  const auto check = [&](const auto& shape, Eigen::VectorXd packed, const Eigen::Vector3d& x) {
    auto s = shape;
    s.unpack(packed);
    std::vector<double> grad(std::size_t(packed.size()));
    const double r0 = s.range_residual(x, packed, grad.data());
    ASSERT_NEAR(r0, s.range_residual(x), 1e-12);  // the same value as the residual the refits minimise
    for (int k = 0; k < packed.size(); ++k) {
      const double h = 1e-7;
      Eigen::VectorXd p = packed, m = packed;
      p(k) += h, m(k) -= h;
      auto sp = shape, sm = shape;
      sp.unpack(p), sm.unpack(m);
      const double numeric = (sp.range_residual(x) - sm.range_residual(x)) / (2 * h);
      EXPECT_NEAR(grad[std::size_t(k)], numeric, 1e-5 * std::max(1.0, std::abs(numeric)))
          << "parameter " << k << " at x = " << x.transpose() << ", parameters " << packed.transpose();
    }
    ++checked;
  };
  for (int trial = 0; trial < 300; ++trial) {
    mereo::shapes::Cylinder c;
    c.point = Eigen::Vector3d(0.3 * U(rng), 0.3 * U(rng), 1.0 + 0.5 * U(rng));
    c.axis = Eigen::Vector3d(U(rng), U(rng), U(rng)).normalized();
    c.radius = 0.03 + 0.05 * std::abs(U(rng));
    Eigen::VectorXd packed = c.pack();
    packed.segment<3>(3) *= 0.5 + std::abs(U(rng));  // the refits' axis drifts from unit length
    // a point near the wall at a random angle, a little off it (some rays graze or miss)
    const Eigen::Vector3d e1 = c.axis.unitOrthogonal(), e2 = c.axis.cross(e1);
    const double phi = M_PI * U(rng);
    const Eigen::Vector3d x = c.point + c.axis * (0.05 * U(rng)) +
                              (c.radius + 0.004 * U(rng)) * (std::cos(phi) * e1 + std::sin(phi) * e2);
    check(c, packed, x);
    mereo::shapes::Sphere s;
    s.center = c.point, s.radius = c.radius;
    check(s, s.pack(), x);
  }
  EXPECT_EQ(checked, 600);
}

namespace {
// A room of rectangles (centre, normal, in-plane u axis, sizes along u and across it), ray-cast
// from an eye at the room frame's origin (x right, y down: gravity, z ahead) into a 640 x 480
// camera (f 525) turned by room_from_camera: exact depth, NaN where no rectangle is hit.
struct RoomRect {
  Eigen::Vector3d c, n, u;
  double su, sv;
};
Cloud ray_cast_room(const std::vector<RoomRect>& rects, const Eigen::Matrix3d& room_from_camera) {
  const int rows = 480, cols = 640;
  const double f = 525, cx = 319.5, cy = 239.5;
  Cloud cloud(rows, cols);
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < cols; ++u) {
      const Eigen::Vector3d ray_c((u - cx) / f, (v - cy) / f, 1.0);
      const Eigen::Vector3d ray = room_from_camera * ray_c;
      double best = INFINITY;
      for (const RoomRect& r : rects) {
        const double den = r.n.dot(ray);
        if (std::abs(den) < 1e-9) continue;
        const double t = r.n.dot(r.c) / den;
        if (!(t > 0) || t >= best) continue;
        const Eigen::Vector3d q = t * ray - r.c, w = r.n.cross(r.u);
        if (std::abs(q.dot(r.u)) <= r.su / 2 && std::abs(q.dot(w)) <= r.sv / 2) best = t;
      }
      const Eigen::Vector3d p = ray_c * best;  // camera frame: ray_c has z = 1
      for (int k = 0; k < 3; ++k) cloud.ptr(v, u)[k] = std::isfinite(best) ? float(p(k)) : NAN;
    }
  return cloud;
}
}  // namespace

// Bounded planar patches against a ray-cast room with exact sizes: a floor 1.3 m below the camera,
// a coffee table's top 0.45 m above it (1.2 x 0.7 m), a wall 4.5 m ahead, and a door leaf standing ajar in
// front of it (a door flush with its wall is one plane with it: depth alone cannot part them), and a box as high as the
// table. Each is one patch with its true size and area; with gravity the upright ones' rectangles stand along it, and
// the table top is open below where the box's top is not.
TEST(Patches, RectanglesOfARayCastRoomHaveTheirTrueSizes) {
  // the camera looks 10 degrees down (the door's top in view); room frame: x right, y down (gravity), z ahead, the eye at
  // its origin 1.3 m above the floor
  const double pitch = 10 * M_PI / 180;
  const Eigen::Matrix3d room_from_camera = Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d eye = Eigen::Vector3d::Zero();  // ray_cast_room's
  using Rect = RoomRect;
  const std::vector<Rect> rects = {
      {{0, 1.3, 3}, {0, -1, 0}, {1, 0, 0}, 8, 8},                // floor
      {{0.2, 0.85, 2.4}, {0, -1, 0}, {1, 0, 0}, 1.2, 0.7},       // a coffee table's top, 0.45 m high
      {{0, -0.2, 4.5}, {0, 0, -1}, {1, 0, 0}, 8, 3},             // wall
      {{-1.3, 0.3, 4.2}, {0.5, 0, -0.866}, {0.866, 0, 0.5}, 0.9, 2.0},   // a door leaf ajar (30 degrees)
      {{1.15, 0.85, 2.6}, {0, -1, 0}, {1, 0, 0}, 0.5, 0.5},              // a box's top as high as the table's
      {{1.15, 1.075, 2.35}, {0, 0, -1}, {1, 0, 0}, 0.5, 0.45},           // ... its front below it
      {{0.9, 1.075, 2.6}, {-1, 0, 0}, {0, 0, 1}, 0.5, 0.45}};            // ... and its side
  const Cloud cloud = ray_cast_room(rects, room_from_camera);
  const NormalMap normals = extension::estimate_normals(cloud);
  const Eigen::Vector3d up = room_from_camera.transpose() * -Eigen::Vector3d::UnitY();
  const auto patches = features::planar_patches(cloud, normals, {}, &up);
  ASSERT_GE(patches.size(), 4u);
  const auto near_to = [&](const Rect& r) -> const shapes::Patch* {
    const Eigen::Vector3d c = room_from_camera.transpose() * (r.c - eye);
    for (const auto& s : patches) {
      const auto& p = s.as<shapes::Patch>();
      if (std::abs(p.normal.dot(room_from_camera.transpose() * r.n)) > 0.999 && std::abs(p.normal.dot(p.point - c)) < 0.01)
        if ((p.point - c).norm() < 0.6 * std::max(r.su, r.sv)) return &p;
    }
    return nullptr;
  };
  // the table top: whole in view, its size and area to within 2 cm and 4%
  const auto* top = near_to(rects[1]);
  ASSERT_NE(top, nullptr);
  EXPECT_NEAR(std::max(top->size_u, top->size_v), 1.2, 0.02);
  EXPECT_NEAR(std::min(top->size_u, top->size_v), 0.7, 0.02);
  EXPECT_NEAR(top->area, 1.2 * 0.7, 0.04 * 1.2 * 0.7);
  EXPECT_NEAR((top->point - room_from_camera.transpose() * (rects[1].c - eye)).norm(), 0.0, 0.02);
  // below the table top's near edge the floor shows far behind it (open: on legs); below the
  // box's, its front at the edge's depth
  const auto* box = near_to(rects[4]);
  ASSERT_NE(box, nullptr);
  EXPECT_GT(top->open_below, 0.9);
  EXPECT_LT(box->open_below, 0.1);
  // the box's front: far depth beyond its right end (the floor, the wall), its own side beyond its
  // left; the door leaf ajar: the wall far behind its nearer edge, close behind its further one
  const auto* front = near_to(rects[5]);
  ASSERT_NE(front, nullptr);
  EXPECT_NEAR(front->stands_out, 0.5, 0.1);
  EXPECT_TRUE(std::isnan(top->stands_out));  // level: not measured
  // the wall runs out of the image at its sides and top; its foot meets the floor; the door leaf
  // stands whole in view
  const auto* wall = near_to(rects[2]);
  ASSERT_NE(wall, nullptr);
  EXPECT_GT(wall->side_cut, 0.9);
  EXPECT_TRUE(wall->top_hidden);
  EXPECT_FALSE(wall->bottom_hidden);
  // the door: upright, so u_axis is horizontal and size_v its height
  const auto* door = near_to(rects[3]);
  ASSERT_NE(door, nullptr);
  EXPECT_LT(std::abs(door->u_axis.dot(up)), 1e-6);
  EXPECT_NEAR(door->size_u, 0.9, 0.02);
  // 4.2 m away, its foot meets the floor: the normals' window bends the normals of a rim there,
  // which PatchOptions::rim gives back to the nearer plane (without it the door is 1.6 cm short)
  EXPECT_NEAR(door->size_v, 2.0, 0.005);
  {
    features::PatchOptions no_rim;
    no_rim.rim = 0;
    const auto short_patches = features::planar_patches(cloud, normals, no_rim, &up);
    double short_door = 0;
    for (const auto& s : short_patches)
      if (std::abs(s.as<shapes::Patch>().size_u - 0.9) < 0.05) short_door = s.as<shapes::Patch>().size_v;
    EXPECT_LT(short_door, 1.99);
  }
  EXPECT_EQ(door->side_cut, 0.0);
  EXPECT_NEAR(door->stands_out, 0.5, 0.1);
  EXPECT_FALSE(door->top_hidden);
  EXPECT_FALSE(door->bottom_hidden);
  // the floor and the wall are single patches, not pieces, and the door is apart from the wall
  ASSERT_NE(near_to(rects[0]), nullptr);
  ASSERT_NE(near_to(rects[2]), nullptr);
  EXPECT_NE(near_to(rects[2]), door);
  std::size_t large = 0;
  std::string areas;
  for (const auto& s : patches) {
    large += s.as<shapes::Patch>().area > 0.3;
    areas += " " + std::to_string(s.as<shapes::Patch>().area);
  }
  EXPECT_EQ(large, 4u) << "areas:" << areas;
  // bad input: sizes that differ
  EXPECT_THROW(features::planar_patches(cloud, NormalMap(2, 2)), InputError);
}

// A level patch's far edge: hidden where something stands on it (a cushion on a side table's rear
// half rises from the top at a concave edge, without a depth step), seen where the floor lies far
// behind it (the same table with nothing on it). Ray-cast: two tops 0.45 m high, 0.5 x 0.45 m,
// the camera 1.3 m above the floor looking 25 degrees down.
TEST(Patches, ALevelPatchsFarEdgeIsHiddenByWhatStandsOnIt) {
  const Eigen::Matrix3d room_from_camera =
      Eigen::AngleAxisd(-25 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d down(0, 1, 0), back(0, 0, -1), x(1, 0, 0);
  const std::vector<RoomRect> rects = {
      {{0, 1.3, 3}, -down, x, 8, 8},                   // floor
      {{0, -0.2, 4.5}, back, x, 8, 3},                 // wall
      {{-0.45, 0.85, 2.2}, -down, x, 0.5, 0.45},       // the loaded table's top
      {{-0.45, 0.75, 2.1}, back, x, 0.5, 0.2},         // the cushion's front, on the top's rear 0.325 m
      {{-0.45, 0.65, 2.2625}, -down, x, 0.5, 0.325},   // ... and its top
      {{0.45, 0.85, 2.2}, -down, x, 0.5, 0.45}};       // the bare table's top
  const Cloud cloud = ray_cast_room(rects, room_from_camera);
  const Eigen::Vector3d up = room_from_camera.transpose() * -down;
  const auto patches = features::planar_patches(cloud, extension::estimate_normals(cloud), {}, &up);
  const auto level_at = [&](double x0, double height) -> const shapes::Patch* {
    for (const auto& s : patches) {
      const auto& p = s.as<shapes::Patch>();
      const Eigen::Vector3d r = room_from_camera * p.point;  // room frame
      if (p.normal.dot(up) > 0.99 && std::abs(r.y() - (1.3 - height)) < 0.01 && std::abs(r.x() - x0) < 0.1) return &p;
    }
    return nullptr;
  };
  const auto* loaded = level_at(-0.45, 0.45);
  const auto* bare = level_at(0.45, 0.45);
  const auto* cushion = level_at(-0.45, 0.65);
  ASSERT_NE(loaded, nullptr);
  ASSERT_NE(bare, nullptr);
  ASSERT_NE(cushion, nullptr);
  EXPECT_TRUE(loaded->far_hidden);
  EXPECT_NEAR(std::min(loaded->size_u, loaded->size_v), 0.125, 0.03);  // the strip before the cushion
  EXPECT_FALSE(bare->far_hidden);
  EXPECT_NEAR(std::min(bare->size_u, bare->size_v), 0.45, 0.03);
  EXPECT_FALSE(cushion->far_hidden);
  // upright patches keep it unset; level ones keep top_hidden, bottom_hidden unset
  for (const auto& s : patches) {
    const auto& p = s.as<shapes::Patch>();
    if (std::abs(p.normal.dot(up)) < 0.5) EXPECT_FALSE(p.far_hidden);
    if (p.normal.dot(up) > 0.99) EXPECT_FALSE(p.top_hidden || p.bottom_hidden);
  }
}

// A patch's sides are read off the weighted quantiles of its pixels (each weighed by its
// footprint): against the brute-force answer (sorted, the first value whose cumulative weight
// reaches the share) on uneven samples, to within one of the 4096 bins over the range.
TEST(Patches, WeightedQuantilesAgreeWithTheSortedAnswer) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  const auto sorted_answer = [](std::vector<std::pair<double, double>> xw, double share) {
    std::sort(xw.begin(), xw.end());
    double total = 0, sum = 0;
    for (const auto& p : xw) total += p.second;
    for (const auto& p : xw)
      if ((sum += p.second) >= share * total) return p.first;
    return xw.back().first;
  };
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 200 + int(5000 * U(rng));
    std::vector<double> x, w;
    std::vector<std::pair<double, double>> xw;
    for (int i = 0; i < n; ++i) {
      // dense at one end, sparse and heavy at the other (a top's near and far ends)
      const double t = U(rng);
      x.push_back(-0.6 + 1.3 * t * t), w.push_back(0.1 + 3 * t);
      xw.emplace_back(x.back(), w.back());
    }
    const double bin = 1.3 / 4096;
    for (const double q : {0.01, 0.02, 0.1}) {
      const auto [lo, hi] = features::detail::weighted_quantiles(x, w, q);
      EXPECT_NEAR(lo, sorted_answer(xw, q), 2 * bin) << "trial " << trial << ", q " << q;
      EXPECT_NEAR(hi, sorted_answer(xw, 1 - q), 2 * bin) << "trial " << trial << ", q " << q;
    }
  }
  // equal weights: the plain quantiles; one value, or none: no range
  std::vector<double> x(1001), w(1001, 1.0);
  for (int i = 0; i <= 1000; ++i) x[std::size_t(i)] = i / 1000.0;
  const auto [lo, hi] = features::detail::weighted_quantiles(x, w, 0.02);
  EXPECT_NEAR(lo, 0.02, 0.002);
  EXPECT_NEAR(hi, 0.98, 0.002);
  EXPECT_EQ(features::detail::weighted_quantiles({0.5}, {1.0}, 0.02), std::make_pair(0.5, 0.5));
  EXPECT_EQ(features::detail::weighted_quantiles({}, {}, 0.02), std::make_pair(0.0, 0.0));
}

// flush: a piece of wall parted from the rest by what stands before it lies in the plane of that
// wall; what stands before it (a pillar's front 0.3 m out, a leaf ajar) does not, nor does the
// larger piece. Ray-cast: a wall 4 m ahead, a pillar 0.4 m wide from floor to ceiling before it,
// leaving a 0.6 m strip of wall at its right, and a door leaf ajar at the left.
TEST(Patches, APieceOfWallBesideWhatPartsItIsFlushWithTheWall) {
  const Eigen::Matrix3d room_from_camera =
      Eigen::AngleAxisd(-10 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d down(0, 1, 0), back(0, 0, -1), x(1, 0, 0);
  const std::vector<RoomRect> rects = {
      {{0, 1.3, 3}, -down, x, 8, 8},                                   // floor
      {{0, 0.0, 4.0}, back, x, 8, 2.6},                                // wall, floor to 2.6 m
      {{0.9, 0.0, 3.7}, back, x, 0.4, 2.6},                            // the pillar's front
      {{0.7, 0.0, 3.85}, -x, Eigen::Vector3d(0, 0, 1), 0.3, 2.6},      // ... its sides
      {{1.1, 0.0, 3.85}, x, Eigen::Vector3d(0, 0, 1), 0.3, 2.6},
      {{-1.3, 0.3, 3.7}, Eigen::Vector3d(0.5, 0, -0.866), Eigen::Vector3d(0.866, 0, 0.5), 0.9, 2.0}};  // a leaf ajar
  const Cloud cloud = ray_cast_room(rects, room_from_camera);
  const Eigen::Vector3d up = room_from_camera.transpose() * -down;
  const auto patches = features::planar_patches(cloud, extension::estimate_normals(cloud), {}, &up);
  // the upright patch whose centre lies nearest to a room point, in the camera frame
  const auto upright_at = [&](const Eigen::Vector3d& room_point) -> const shapes::Patch* {
    const Eigen::Vector3d c = room_from_camera.transpose() * room_point;
    const shapes::Patch* best = nullptr;
    for (const auto& s : patches) {
      const auto& p = s.as<shapes::Patch>();
      if (std::abs(p.normal.dot(up)) < 0.1 && (!best || (p.point - c).norm() < (best->point - c).norm())) best = &p;
    }
    return best;
  };
  const auto* wall = upright_at({-0.5, 0.0, 4.0});
  const auto* strip = upright_at({1.8, 0.0, 4.0});
  const auto* pillar = upright_at({0.9, 0.0, 3.7});
  const auto* leaf = upright_at({-1.3, 0.3, 3.7});
  ASSERT_TRUE(wall && strip && pillar && leaf);
  ASSERT_NE(wall, strip);
  EXPECT_GT(wall->area, strip->area);
  EXPECT_LT(std::abs(strip->normal.dot(wall->point - strip->point)), 0.01);  // one plane
  EXPECT_TRUE(strip->flush);
  EXPECT_FALSE(wall->flush);
  EXPECT_FALSE(pillar->flush);
  EXPECT_FALSE(leaf->flush);
  EXPECT_EQ(*strip->attribute("flush"), 1.0);
  EXPECT_EQ(*wall->attribute("flush"), 0.0);
}
