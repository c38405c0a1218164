// The cognitive layer: tracks keep one id while their parts stay consistent across views; a
// hypothesis whose part drifts away from its body, or whose body is then taken for something
// else, is dropped within a few frames; the Kalman filter beats a single view; unseen tracks
// decay and go; the tracking node runs in frame order in the parallel mode too; odometry
// recovers the orbiting camera's motion.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "../bench/bench_util.hpp"
#include "../bench/eval_tracking.hpp"
#include "mereo/cognitive/landmarks.hpp"
#include "mereo/cognitive/odometry.hpp"
#include "mereo/cognitive/relations.hpp"
#include "mereo/cognitive/tracking.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
using cognitive::Observation;

namespace {

/// A mug in the world (body at `centre`, handle beside it) seen from a camera at `pose`, with
/// `noise` (metres) on the radius and the handle's position.
Observation mug_seen(const Pose& pose, const Eigen::Vector3d& centre, std::mt19937_64& rng, double noise,
                     const Eigen::Vector3d& handle_shift = Eigen::Vector3d::Zero(), const std::string& model = "mug") {
  std::normal_distribution<double> n(0.0, noise);
  const Pose to_camera = pose.inverse();
  Segment body;
  body.shape = shapes::Cylinder{};
  body.as<shapes::Cylinder>().point = centre, body.as<shapes::Cylinder>().axis = Eigen::Vector3d::UnitZ(), body.as<shapes::Cylinder>().radius = 0.04 + n(rng), body.as<shapes::Cylinder>().height = 0.1;
  Segment handle;
  handle.shape = shapes::Torus{};
  handle.as<shapes::Torus>().center = centre + Eigen::Vector3d(0.055, 0, 0) + handle_shift + Eigen::Vector3d(n(rng), n(rng), n(rng));
  handle.as<shapes::Torus>().normal = Eigen::Vector3d::UnitY(), handle.as<shapes::Torus>().major_radius = 0.025, handle.as<shapes::Torus>().minor_radius = 0.006;
  Observation o;
  o.model = model, o.score = 0.95, o.accepted = true;
  o.parts = {{"body", cognitive::transformed(body, to_camera)}};
  if (model == "mug") o.parts.push_back({"handle", cognitive::transformed(handle, to_camera)});
  o.segments = {0, 1};
  return o;
}

/// Camera k of an orbit around the origin, 6 degrees apart, 1 m away, looking at the origin.
Pose orbit(int k) { return synthetic::orbit_pose(Eigen::Vector3d::Zero(), 1.0, 40.0, 6.0 * k); }

}  // namespace

TEST(Tracking, ConsistentPartsKeepOneIdAndTheFilterBeatsOneView) {
  cognitive::Tracker tracker;
  std::mt19937_64 rng(1);
  const Eigen::Vector3d centre(0.05, -0.02, 0.05);
  std::vector<double> single, fused;
  int id = -1;
  for (int k = 0; k < 30; ++k) {
    const auto obs = mug_seen(orbit(k), centre, rng, 0.002);
    single.push_back(std::abs(obs.parts[0].second.size() - 0.04));
    const auto& tracks = tracker.update({obs}, orbit(k));
    ASSERT_EQ(tracks.size(), 1u);
    if (id < 0) id = tracks[0].id;
    EXPECT_EQ(tracks[0].id, id);
    // one view does not make a report; the second that agrees does
    if (k == 0) EXPECT_LT(tracks[0].probability(), 0.5);
    else EXPECT_GE(tracks[0].probability(), 0.5);
    if (k >= 10) fused.push_back(std::abs(tracks[0].parts[0].world.size() - 0.04));
  }
  EXPECT_LT(bench::median(fused), 0.5 * bench::median(single));
  EXPECT_LT((tracker.tracks()[0].parts[0].world.origin() - centre).head<2>().norm(), 0.002);
}

namespace {
/// Whether `tracker` reports a track of `id` (all when -1) at its `report` probability.
bool reported(const cognitive::Tracker& tracker, int id = -1) {
  for (const auto& t : tracker.tracks())
    if ((id < 0 || t.id == id) && t.probability() >= tracker.options().report) return true;
  return false;
}
}  // namespace

TEST(Tracking, PartsDriftingApartOrAContradictedBodyAreRejected) {
  std::mt19937_64 rng(2);
  const Eigen::Vector3d centre(0.0, 0.1, 0.05);
  // a ring beside a jar: from each view the "handle" sits somewhere else relative to the body
  // (the first two views agree: it is reported; then the ring is seen from elsewhere)
  cognitive::Tracker drifting;
  int first_reported = -1, dropped_at = -1;
  for (int k = 0; k < 10 && dropped_at < 0; ++k) {
    const Eigen::Vector3d shift =
        k < 2 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.0, 0.03 * std::sin(0.9 * k), 0.02 * std::cos(0.7 * k));
    drifting.update({mug_seen(orbit(k), centre, rng, 0.0005, shift)}, orbit(k));
    if (reported(drifting) && first_reported < 0) first_reported = k;
    if (!reported(drifting) && first_reported >= 0) dropped_at = k;
  }
  ASSERT_EQ(first_reported, 1);
  ASSERT_GE(dropped_at, 2);
  EXPECT_LE(dropped_at - first_reported, 5);
  // rejected, it is held with the evidence against it: a next view that supports it does not
  // start it afresh
  const int id = drifting.tracks().at(0).id;
  const int k = dropped_at + 1;
  drifting.update({mug_seen(orbit(k), centre, rng, 0.0005, Eigen::Vector3d(0, -0.02, 0.01))}, orbit(k));
  ASSERT_EQ(drifting.tracks().size(), 1u);
  EXPECT_EQ(drifting.tracks()[0].id, id);
  EXPECT_FALSE(reported(drifting));
  // a body taken for a mug from two views, then for a jar from the next views
  cognitive::Tracker contradicted;
  for (int k = 0; k < 2; ++k) contradicted.update({mug_seen(orbit(k), centre, rng, 0.0005)}, orbit(k));
  ASSERT_EQ(contradicted.tracks().size(), 1u);
  const int mug_id = contradicted.tracks()[0].id;
  ASSERT_TRUE(reported(contradicted, mug_id));
  int frames = 0;
  for (int k = 2; k <= 7; ++k) {
    contradicted.update({mug_seen(orbit(k), centre, rng, 0.0005, {}, "jar")}, orbit(k));
    if (!reported(contradicted, mug_id)) break;
    ++frames;
  }
  EXPECT_LE(frames, 4);
}

namespace {
/// A depth image of `value` everywhere (NaN: none), VGA.
DepthImage flat_depth(float value) {
  DepthImage d(480, 640);
  for (int v = 0; v < d.rows(); ++v)
    for (int u = 0; u < d.cols(); ++u) d(v, u) = value;
  return d;
}
}  // namespace

TEST(Tracking, PartVisibilityReadsTheDepthWhereThePartIsHeld) {
  // a handle facing the camera 1 m away (ring in the image plane), its body to the left
  Segment body;
  body.shape = shapes::Cylinder{};
  body.as<shapes::Cylinder>().point = Eigen::Vector3d(-0.055, 0, 1.0), body.as<shapes::Cylinder>().axis = Eigen::Vector3d::UnitY(), body.as<shapes::Cylinder>().radius = 0.04;
  Segment handle;
  handle.shape = shapes::Torus{};
  handle.as<shapes::Torus>().center = Eigen::Vector3d(0, 0, 1.0), handle.as<shapes::Torus>().normal = Eigen::Vector3d::UnitZ(), handle.as<shapes::Torus>().major_radius = 0.025;
  handle.as<shapes::Torus>().minor_radius = 0.006;
  const Intrinsics K;
  // 36 points on the ring; those within the body's wall or within the tolerance (1 cm) and the
  // tube radius of it (x < -0.055 + 0.04 + 0.006 + 0.01) are not looked at
  int outside = 0;
  for (int k = 0; k < 36; ++k) outside += -0.055 + 0.056 <= 0.025 * std::cos(2 * M_PI * k / 36);
  ASSERT_GT(outside, 10);
  const auto there = cognitive::part_visibility(handle, body, flat_depth(1.0f), K);
  EXPECT_EQ(there.total(), outside);
  EXPECT_EQ(there.there, outside);
  // each point stands for 1/36 of the ring's length times the tube's width, at 525 pixels per metre
  EXPECT_NEAR(there.pixels, outside * (2 * M_PI * 0.025 / 36) * 0.012 * 525 * 525, 1e-6);
  const auto through = cognitive::part_visibility(handle, body, flat_depth(1.5f), K);  // the wall behind it
  EXPECT_EQ(through.through, outside);
  const auto occluded = cognitive::part_visibility(handle, body, flat_depth(0.6f), K);  // something in front
  EXPECT_EQ(occluded.occluded, outside);
  const auto unknown = cognitive::part_visibility(handle, body, flat_depth(kNaN), K);
  EXPECT_EQ(unknown.unknown, outside);
  EXPECT_EQ(unknown.seen(), 0);
  EXPECT_EQ(unknown.pixels, 0.0);
  // the points around it: the ring's (a surface at its depth), none off its reach
  DepthImage d = flat_depth(kNaN);
  for (int v = 220; v <= 260; ++v)
    for (int u = 300; u <= 340; ++u) d(v, u) = 1.0f;
  const auto pts = cognitive::points_around(handle, body, d, K, 0.005, 10000);
  ASSERT_FALSE(pts.empty());
  for (const auto& p : pts) {
    EXPECT_LE((p - handle.as<shapes::Torus>().center).norm(), 0.025 + 0.006 + 0.005 + 1e-9);
    EXPECT_GE(std::hypot(p.x() - body.as<shapes::Cylinder>().point.x(), p.z() - body.as<shapes::Cylinder>().point.z()), 0.045 - 1e-9);
  }
}

TEST(Tracking, AContradictionCountsAsFarAsTheViewShowsThePart) {
  // a mug taken for a mug from two views, then for a jar (its handle not found) from the next
  const Eigen::Vector3d centre(0.0, 0.05, 0.05);
  auto run = [&](float depth_after) {
    cognitive::Tracker tracker;
    std::mt19937_64 rng(5);
    const DepthImage far = flat_depth(kNaN);
    for (int k = 0; k < 2; ++k) tracker.update({mug_seen(orbit(k), centre, rng, 0.0005)}, orbit(k), &far, Intrinsics{});
    const int mug = tracker.tracks().at(0).id;
    const DepthImage after = flat_depth(depth_after);
    int reported_views = 0;
    for (int k = 2; k < 8; ++k) {
      tracker.update({mug_seen(orbit(k), centre, rng, 0.0005, {}, "jar")}, orbit(k), &after, Intrinsics{});
      reported_views += reported(tracker, mug);
    }
    return reported_views;
  };
  // something in front of the handle in every later view: no evidence, the mug stays
  EXPECT_EQ(run(0.3f), 6);
  // no depth where the handle is: no evidence either
  EXPECT_EQ(run(kNaN), 6);
  // the views see through where the handle is held: not a mug, at once
  EXPECT_EQ(run(5.0f), 0);
}

TEST(Tracking, APartKeepsItsPlaceWhenTheBodyIsPartlyHidden) {
  // the body's centre is the middle of its visible extent: with its lower half hidden from some
  // views it moves up 2.5 cm while the handle stays; the handle has not drifted
  cognitive::Tracker tracker;
  std::mt19937_64 rng(6);
  const Eigen::Vector3d centre(0.03, 0.0, 0.05);
  for (int k = 0; k < 8; ++k) {
    auto obs = mug_seen(orbit(k), centre, rng, 0.0005);
    if (k % 2) {
      const Pose to_camera = orbit(k).inverse();
      obs.parts[0].second.as<shapes::Cylinder>().point += to_camera.linear() * Eigen::Vector3d(0, 0, 0.025);
      obs.parts[0].second.as<shapes::Cylinder>().height = 0.05;
    }
    tracker.update({obs}, orbit(k));
    ASSERT_EQ(tracker.tracks().size(), 1u);
    EXPECT_FALSE(tracker.tracks()[0].parts[1].moved_to.has_value()) << "view " << k;
  }
  EXPECT_GT(tracker.tracks()[0].probability(), 0.99);
}

TEST(Tracking, APartFirstFittedOffIsReanchoredAndTheTrackKeepsItsId) {
  // the first view fits the handle 2 cm off; every later view sees it where it is
  cognitive::Tracker tracker;
  std::mt19937_64 rng(4);
  const Eigen::Vector3d centre(0.02, 0.03, 0.05);
  tracker.update({mug_seen(orbit(0), centre, rng, 0.0005, Eigen::Vector3d(0, 0.02, 0))}, orbit(0));
  const int id = tracker.tracks().at(0).id;
  for (int k = 1; k < 8; ++k) tracker.update({mug_seen(orbit(k), centre, rng, 0.0005)}, orbit(k));
  ASSERT_EQ(tracker.tracks().size(), 1u);
  EXPECT_EQ(tracker.tracks()[0].id, id);
  EXPECT_TRUE(reported(tracker, id));
  const auto* handle = tracker.tracks()[0].part("handle");
  ASSERT_NE(handle, nullptr);
  EXPECT_LT((handle->world.origin() - (centre + Eigen::Vector3d(0.055, 0, 0))).norm(), 0.003);
}

TEST(Tracking, UnseenTracksDecayAndGo) {
  cognitive::TrackOptions o;
  o.max_missed = 5;
  cognitive::Tracker tracker(o);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 4; ++k) tracker.update({mug_seen(orbit(k), {0, 0, 0.05}, rng, 0.0005)}, orbit(k));
  const double p = tracker.tracks()[0].probability();
  tracker.update({}, orbit(4));
  ASSERT_EQ(tracker.tracks().size(), 1u);
  EXPECT_LT(tracker.tracks()[0].probability(), p);
  EXPECT_FALSE(tracker.tracks()[0].seen);
  for (int k = 5; k < 11; ++k) tracker.update({}, orbit(k));
  EXPECT_TRUE(tracker.tracks().empty());
}

TEST(TrackingGraph, OrderedNodeGivesTheSameTracksInBothModes) {
  const auto seq = synthetic::render_sequence(703, 8);
  std::vector<Frame> frames;
  for (const auto& f : seq) frames.push_back(f.frame);
  graph::Graph g = graph::Graph::load(std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop_tracking.yaml");
  std::vector<std::vector<std::string>> lines(2);
  for (int m = 0; m < 2; ++m) {
    graph::RunOptions o;
    o.mode = m == 0 ? graph::Mode::Deterministic : graph::Mode::Parallel;
    o.max_in_flight = 4;
    o.keep = {"result.result"};
    for (auto& r : g.run_all(graph::FrameSource::recorded(frames), o))
      lines[m].push_back(r.outputs.at("result.result").get<std::string>());
  }
  EXPECT_EQ(lines[0], lines[1]);
  const auto last = nlohmann::json::parse(lines[0].back());
  ASSERT_FALSE(last["objects"].empty());
  for (const auto& o : last["objects"]) EXPECT_TRUE(o.contains("track"));
}

TEST(TrackingGraph, RingsLeaningOnJarsAreDroppedAndMugsKeepTheirTracks) {
  // the orbits of seeds 700, 702 and 720: a ring leaning on a jar passed for a mug's handle from
  // several views (seed 720: from four views in a row, its first, nearly edge-on) until the jar's
  // lid was looked at (Segment::end_closed: a mug is open). A view fooled still must be dropped
  // within 5 frames (Tracking.PartsDriftingApartOrAContradictedBodyAreRejected fools it on purpose)
  graph::Graph g = graph::Graph::load(std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop_tracking.yaml");
  bench::TrackingScore score;
  for (std::uint64_t seed : {700, 702, 720}) {
    synthetic::SceneOptions so;
    so.ambiguous_distractors = true;
    const auto seq = synthetic::render_sequence(seed, 30, so);
    std::vector<Frame> frames;
    for (const auto& f : seq) frames.push_back(f.frame);
    graph::RunOptions o;
    o.keep = {"tracks.tracks"};
    std::vector<std::vector<cognitive::Track>> tracks;
    for (auto& r : g.run_all(graph::FrameSource::recorded(frames), o))
      tracks.push_back(r.outputs.at("tracks.tracks").get<std::vector<cognitive::Track>>());
    bench::score_sequence(seq, tracks, "seed " + std::to_string(seed), score);
  }
  for (const auto& n : score.notes) std::printf("[ tracking ] %s\n", n.c_str());
  std::printf("[ tracking ] %d views fooled (%d reported), %d false mug reports, %d dropped within 5 frames; %d/%d mugs "
              "lost, %d id switches\n",
              score.false_mug_views, score.false_mug_views_reported, score.false_mugs, score.false_mugs_dropped_in_5,
              score.true_mugs_lost, score.true_mugs, score.id_switches);
  EXPECT_LE(score.false_mug_views, 1);  // 16 views fooled, 2 false tracks before the end view
  EXPECT_GE(score.false_mugs_dropped_in_5, 0.9 * score.false_mugs);
  EXPECT_GE(score.true_mugs, 2);
  EXPECT_EQ(score.true_mugs_lost, 0);
  EXPECT_EQ(score.id_switches, 0);
}

TEST(Odometry, FollowsTheOrbitingCamera) {
  const auto seq = synthetic::render_sequence(700, 8);  // 30 degrees of elevation: objects in view
  cognitive::Odometry odometry;
  std::vector<Pose> poses;
  for (const auto& f : seq) poses.push_back(odometry.update(f.frame));
  std::vector<double> mm, deg;
  for (std::size_t k = 1; k < seq.size(); ++k) {
    const Pose truth = seq[k - 1].truth.camera_pose.inverse() * seq[k].truth.camera_pose;
    const Pose err = truth.inverse() * (poses[k - 1].inverse() * poses[k]);
    mm.push_back(1000 * err.translation().norm());
    deg.push_back(Eigen::AngleAxisd(err.linear()).angle() * 180 / M_PI);
  }
  EXPECT_LT(bench::median(mm), 5.0);
  EXPECT_LT(bench::median(deg), 0.5);
  EXPECT_EQ(odometry.lost(), 0u);
}

namespace {

/// Upright cylinders standing on the world's table (z = 0) at `feet` with `radii`, as a camera at
/// `pose` sees them (camera frame), and the table's plane in that camera's frame.
std::vector<Segment> cylinders_seen(const Pose& pose, const std::vector<Eigen::Vector2d>& feet,
                                    const std::vector<double>& radii) {
  std::vector<Segment> out;
  const Pose to_camera = pose.inverse();
  for (std::size_t i = 0; i < feet.size(); ++i) {
    Segment s;
    s.shape = shapes::Cylinder{};
    s.as<shapes::Cylinder>().point = Eigen::Vector3d(feet[i].x(), feet[i].y(), 0.05), s.as<shapes::Cylinder>().axis = Eigen::Vector3d::UnitZ();
    s.as<shapes::Cylinder>().radius = radii[i], s.as<shapes::Cylinder>().height = 0.08, s.inliers = 1000;
    out.push_back(cognitive::transformed(s, to_camera));
  }
  return out;
}

cognitive::TablePlane table_seen(const Pose& pose) {
  const Pose to_camera = pose.inverse();
  cognitive::TablePlane p;
  p.normal = to_camera.linear() * Eigen::Vector3d::UnitZ();
  p.d = -p.normal.dot(to_camera * Eigen::Vector3d::Zero());
  return p;
}

double pose_error_mm(const Pose& a, const Pose& b) { return 1000 * (a.inverse() * b).translation().norm(); }
double pose_error_deg(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle() * 180 / M_PI;
}

}  // namespace

TEST(Landmarks, TheTableAndTwoCylindersFixThePoseFromAFarGuess) {
  const std::vector<Eigen::Vector2d> feet = {{0.1, 0.05}, {-0.15, 0.1}, {0.02, -0.2}, {0.2, -0.1}};
  const std::vector<double> radii = {0.04, 0.035, 0.045, 0.03};
  // the map from the first view (camera 0 is the world origin: poses relative to it)
  const Pose world = orbit(0);  // truth's camera 0 in the table's frame
  cognitive::LandmarkMap map;
  cognitive::add_to_map(map, table_seen(world), cylinders_seen(world, feet, radii), Pose::Identity());
  ASSERT_EQ(map.landmarks.size(), 4u);
  for (int k : {3, 8, 20}) {
    const Pose truth = world.inverse() * orbit(k);  // camera k relative to camera 0
    // a guess 20 cm and 15 degrees off, as a frame-to-frame odometry sliding along the table gives
    Pose guess = truth;
    guess.translation() += Eigen::Vector3d(0.15, -0.1, 0.08);
    guess.linear() = guess.linear() * Eigen::AngleAxisd(0.26, Eigen::Vector3d::UnitY()).toRotationMatrix();
    // this view misses one cylinder and sees a spurious one
    auto seen_feet = feet, extra = std::vector<Eigen::Vector2d>{{-0.3, -0.25}};
    auto seen_radii = radii;
    seen_feet.erase(seen_feet.begin() + 1), seen_radii.erase(seen_radii.begin() + 1);
    seen_feet.push_back(extra[0]), seen_radii.push_back(0.04);
    const auto fix = cognitive::locate(map, table_seen(orbit(k)), cylinders_seen(orbit(k), seen_feet, seen_radii), guess);
    EXPECT_TRUE(fix.plane);
    EXPECT_EQ(fix.observed, 4);
    EXPECT_EQ(fix.matched, 3);
    EXPECT_LT(pose_error_mm(fix.camera_to_world, truth), 0.01) << "view " << k;
    EXPECT_LT(pose_error_deg(fix.camera_to_world, truth), 1e-4) << "view " << k;
  }
}

TEST(Landmarks, WithoutTheTableOrLandmarksTheGuessStands) {
  const std::vector<Eigen::Vector2d> feet = {{0.1, 0.05}, {-0.15, 0.1}};
  const std::vector<double> radii = {0.04, 0.035};
  const Pose world = orbit(0);
  cognitive::LandmarkMap map;
  cognitive::add_to_map(map, table_seen(world), cylinders_seen(world, feet, radii), Pose::Identity());
  const Pose truth = world.inverse() * orbit(5);
  Pose guess = truth;
  guess.translation() += Eigen::Vector3d(0.01, 0.0, 0.0);
  // a plane 40 degrees off the map's table under the guess is not the table: the guess stands
  cognitive::TablePlane wall = table_seen(orbit(5));
  wall.normal = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) * wall.normal;
  auto fix = cognitive::locate(map, wall, cylinders_seen(orbit(5), feet, radii), guess);
  EXPECT_FALSE(fix.plane);
  EXPECT_LT(pose_error_mm(fix.camera_to_world, guess), 1e-6);
  // no cylinders in view: the table fixes tilt and height, the guess keeps the turn and slide
  fix = cognitive::locate(map, table_seen(orbit(5)), {}, guess);
  EXPECT_TRUE(fix.plane);
  EXPECT_EQ(fix.matched, 0);
  EXPECT_NEAR(pose_error_mm(fix.camera_to_world, truth), 10.0, 0.5);
  // cylinders of other radii are not landmarks of these
  fix = cognitive::locate(map, table_seen(orbit(5)), cylinders_seen(orbit(5), feet, {0.07, 0.02}), guess);
  EXPECT_EQ(fix.matched, 0);
}

TEST(Landmarks, ARingBesideTheOnlyCylinderBoundsTheTurn) {
  // a mug: its body's axis at (0.1, 0.05), its handle's ring 5.5 cm beside it (ring plane through
  // the axis); a plane and one cylinder leave the turn about the axis free, the ring fixes it
  // (less precisely than a second axis: it bounds the guess's turn)
  const Eigen::Vector2d foot(0.1, 0.05);
  auto seen = [&](const Pose& pose, bool ring, double ring_error = 0.0) {
    auto out = cylinders_seen(pose, {foot}, {0.04});
    if (!ring) return out;
    Segment t;
    t.shape = shapes::Torus{};
    // the ring's centre, off by `ring_error` across the body-to-ring direction
    t.as<shapes::Torus>().center = Eigen::Vector3d(foot.x() + 0.055, foot.y() + ring_error, 0.05), t.as<shapes::Torus>().normal = Eigen::Vector3d::UnitY();
    t.as<shapes::Torus>().major_radius = 0.025, t.as<shapes::Torus>().minor_radius = 0.006, t.inliers = 300;
    out.push_back(cognitive::transformed(t, pose.inverse()));
    return out;
  };
  const Pose world = orbit(0);
  cognitive::LandmarkMap map;
  cognitive::add_to_map(map, table_seen(world), seen(world, true), Pose::Identity());
  ASSERT_EQ(map.landmarks.size(), 2u);
  const Pose truth = world.inverse() * orbit(4);
  auto turned = [&](double deg) {  // the guess turned about the body's axis (world: camera 0)
    const Eigen::Vector3d axis = table_seen(world).normal;
    const Eigen::Vector3d at = world.inverse() * Eigen::Vector3d(foot.x(), foot.y(), 0.0);
    Pose R = Pose::Identity();
    R.linear() = Eigen::AngleAxisd(deg * M_PI / 180, axis).toRotationMatrix();
    R.translation() = at - R.linear() * at;
    return Pose(R * truth);
  };
  // without the ring, a guess turned 10 degrees about the body keeps its turn
  auto fix = cognitive::locate(map, table_seen(orbit(4)), seen(orbit(4), false), turned(10));
  EXPECT_EQ(fix.matched, 1);
  EXPECT_NEAR(pose_error_deg(fix.camera_to_world, truth), 10.0, 0.01);
  // with it, the turn is brought back within the tolerance (3 degrees) of the ring's
  fix = cognitive::locate(map, table_seen(orbit(4)), seen(orbit(4), true), turned(10));
  EXPECT_EQ(fix.matched, 2);
  EXPECT_NEAR(pose_error_deg(fix.camera_to_world, truth), 3.0, 0.01);
  // a guess within the tolerance is kept (a ring fitted 1 mm off turns the rings' 1 degree), the
  // slide still put right by the axis
  fix = cognitive::locate(map, table_seen(orbit(4)), seen(orbit(4), true, 0.001), turned(1));
  EXPECT_NEAR(pose_error_deg(fix.camera_to_world, truth), 1.0, 0.01);
  const Eigen::Vector3d body = world.inverse() * Eigen::Vector3d(foot.x(), foot.y(), 0.0);
  EXPECT_LT(1000 * (fix.camera_to_world * (truth.inverse() * body) - body).norm(), 1.0);
  // a ring is not a cylinder's landmark, nor a cylinder a ring's
  cognitive::LandmarkMap rings;
  cognitive::add_to_map(rings, table_seen(world), {seen(world, true).back()}, Pose::Identity());
  fix = cognitive::locate(rings, table_seen(orbit(4)), seen(orbit(4), false), turned(10));
  EXPECT_EQ(fix.matched, 0);
}

TEST(Odometry, LandmarksHoldTheCameraWhereIcpSlidesAlongTheTable) {
  // seed 701: a steep view (55 degrees) of the untextured table, where frame-to-frame ICP slides
  const auto seq = synthetic::render_sequence(701, 16);
  std::vector<Frame> frames;
  for (const auto& f : seq) frames.push_back(f.frame), frames.back().pose.reset();
  graph::Graph g = graph::Graph::load(std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop_odometry.yaml");
  graph::RunOptions o;
  o.keep = {"poses.frame"};
  std::vector<Pose> poses;
  for (auto& r : g.run_all(graph::FrameSource::recorded(frames), o)) poses.push_back(*r.outputs.at("poses.frame").get<Frame>().pose);
  ASSERT_EQ(poses.size(), seq.size());
  double worst = 0;
  for (std::size_t k = 1; k < seq.size(); ++k) {
    const Pose truth = seq[k - 1].truth.camera_pose.inverse() * seq[k].truth.camera_pose;
    worst = std::max(worst, pose_error_mm(truth, poses[k - 1].inverse() * poses[k]));
  }
  const Pose truth_end = seq.front().truth.camera_pose.inverse() * seq.back().truth.camera_pose;
  std::printf("[ odometry ] seed 701: worst step %.1f mm, last frame %.1f mm off\n", worst,
              pose_error_mm(truth_end, poses.back()));
  EXPECT_LT(worst, 10.0);
  EXPECT_LT(pose_error_mm(truth_end, poses.back()), 10.0);
}

TEST(Odometry, AFailedAlignmentGivesWayToTheLastMotion) {
  // seed 716 (rings leaning on jars), its orbit's first 40 frames: somewhere the alignment slides
  // off by several centimetres (where depends on the landmarks the primitive search finds, so on
  // its random draws: frame 22 by 29 cm before rings were landmarks, ~5 cm after; frame 26 by 6 cm
  // with another sampler); the last motion stands in. Worst steps seen without the check / with
  // it: 44.3 / 9.0 mm, 44.9 / 9.4 and 58.3 / 8.1 (three samplers), 33.5 / 9.0 (closed-form refit
  // Jacobians); a step stays within a few millimetres where the alignment holds
  synthetic::SceneOptions so;
  so.ambiguous_distractors = true;
  const synthetic::Scene scene = synthetic::generate_scene(716, so);
  std::vector<synthetic::SyntheticFrame> seq;
  std::vector<Frame> frames;
  for (int k = 0; k < 40; ++k) {
    seq.push_back(synthetic::render(scene, synthetic::orbit_view(scene, k, so), so, k));
    frames.push_back(seq.back().frame), frames.back().pose.reset();
  }
  auto worst_step = [&](double max_jump) {
    graph::Graph g = graph::Graph::load(std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop_odometry.yaml");
    g.set_options("poses", {{"max_jump", max_jump}});
    graph::RunOptions o;
    o.keep = {"poses.frame"};
    std::vector<Pose> poses;
    for (auto& r : g.run_all(graph::FrameSource::recorded(frames), o))
      poses.push_back(*r.outputs.at("poses.frame").get<Frame>().pose);
    double worst = 0;
    for (std::size_t k = 1; k < seq.size(); ++k) {
      const Pose truth = seq[k - 1].truth.camera_pose.inverse() * seq[k].truth.camera_pose;
      worst = std::max(worst, pose_error_mm(truth, poses[k - 1].inverse() * poses[k]));
    }
    return worst;
  };
  const double gated = worst_step(cognitive::OdometryOptions{}.max_jump), free = worst_step(100.0);
  std::printf("[ odometry ] seed 716, frames 0-39: worst step %.1f mm, %.1f mm without the check\n", gated, free);
  EXPECT_GT(free, 25.0);  // the failure is there
  EXPECT_LT(gated, 15.0);
}

// Scene relations (cognitive/relations.hpp) on an analytic scene: a table 0.5 m below the camera
// (support normal -y), a cup on a plate, a can beside the plate, a jar behind the can as the
// camera sees it, a box known only as an unknown region's box, and a ball floating 25 cm up.
TEST(Relations, OnNextToAndInFrontOfFromTheObjectsShapes) {
  const Eigen::Vector3d up(0, -1, 0);
  const double d = 0.5;  // up.dot(x) + d = 0 at y = 0.5
  const auto standing = [&](double x, double z, double r, double h, double base = 0) {
    shapes::Cylinder c;
    c.point = Eigen::Vector3d(x, 0.5 - base - h / 2, z), c.axis = up, c.radius = r, c.height = h;
    return Segment{Geometry(c)};
  };
  shapes::Sphere ball;
  ball.center = Eigen::Vector3d(0.5, 0.5 - 0.3, 0.9), ball.radius = 0.05;
  std::vector<cognitive::PlacedObject> objects(6);
  objects[0].id = 10, objects[0].parts = {standing(0, 1.2, 0.1, 0.015)};            // plate
  objects[1].id = 11, objects[1].parts = {standing(0.01, 1.2, 0.04, 0.1, 0.015)};   // cup on it
  objects[2].id = 12, objects[2].parts = {standing(0.18, 1.2, 0.033, 0.12)};        // can
  objects[3].id = 13, objects[3].parts = {standing(0.24, 1.6, 0.04, 0.1)};          // jar behind it
  objects[4].id = 14, objects[4].parts = {Segment{Geometry(ball)}};
  objects[5].id = 15, objects[5].box_centre = Eigen::Vector3d(-0.3, 0.5 - 0.1, 1.0);
  objects[5].box_size = Eigen::Vector3d(0.1, 0.1, 0.2);
  auto got = cognitive::scene_relations(objects, up, d);
  const int S = cognitive::Relation::kSupport;
  std::vector<cognitive::Relation> want = {{"on", 10, S}, {"on", 11, 10}, {"on", 12, S}, {"on", 13, S}, {"on", 15, S},
                                           {"next_to", 10, 12}, {"in_front_of", 12, 13}};
  const auto key = [](const cognitive::Relation& r) { return std::make_tuple(r.relation, r.subject, r.object); };
  const auto by_key = [&](const auto& a, const auto& b) { return key(a) < key(b); };
  std::sort(got.begin(), got.end(), by_key), std::sort(want.begin(), want.end(), by_key);
  EXPECT_EQ(got, want);
  // lifted by 5 cm, the can rests on nothing (and is next to nothing)
  objects[2].parts = {standing(0.18, 1.2, 0.033, 0.12, 0.05)};
  got = cognitive::scene_relations(objects, up, d);
  for (const auto& r : got) EXPECT_TRUE(r.subject != 12 || r.relation == "in_front_of") << r.relation << " " << r.object;
  EXPECT_THROW(cognitive::scene_relations(objects, Eigen::Vector3d(0, -2, 0), d), InputError);
}
