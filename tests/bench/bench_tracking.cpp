// bench_tracking: the cognitive layer over rendered sequences (the camera orbiting the table,
// handle-like rings leaning on jars: from some views they pass for a mug's handle):
// graphs/tabletop_tracking.yaml with the renderer's poses, and graphs/tabletop_odometry.yaml
// with the poses estimated by the odometry node (OpenCV's RGB-D ICP
// odometry, the reference of the poses being the renderer's). Per setting: false mug tracks
// and how many are dropped within 5 frames, true mugs lost, id switches per 100 frames, the
// median radius error of one view and after ten (eval_tracking.hpp), time per frame; for the
// odometry, its error per frame against the true relative motion. The last line is one JSON
// object.
//
//   bench_tracking            8 sequences (seeds 700-707) of 30 frames
//   bench_tracking --quick    2 sequences of 12 frames (ctest)
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "bench_util.hpp"
#include "eval_tracking.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/io/io.hpp"

using namespace mereo;
using bench::median;
using bench::now_ms;

namespace {

struct Setting {
  std::string name;
  bench::TrackingScore score;
  std::vector<double> ms;
  std::vector<double> drift_mm, drift_deg;  // odometry: per frame, against the true relative motion
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--quick") quick = true;
  const int sequences = quick ? 2 : 8, frames = quick ? 12 : 30;
  Setting given{"poses given"}, estimated{"poses by odometry"};
  for (Setting* s : {&given, &estimated}) {
    // the odometry's graph: the frames' poses estimated (they come without poses here, so the
    // support plane finds the table without gravity)
    graph::Graph g = graph::Graph::load(std::string(MEREO_SOURCE_DIR) +
                                        (s == &given ? "/graphs/tabletop_tracking.yaml" : "/graphs/tabletop_odometry.yaml"));
    for (int q = 0; q < sequences; ++q) {
      synthetic::SceneOptions so;
      so.ambiguous_distractors = true;
      const std::uint64_t seed = 700 + std::uint64_t(q);
      const auto seq = synthetic::render_sequence(seed, frames, so);
      std::vector<Frame> input;
      for (const auto& f : seq) {
        input.push_back(f.frame);
        if (s == &estimated) input.back().pose.reset();
      }
      graph::RunOptions o;
      o.keep = {"tracks.tracks"};
      if (s == &estimated) o.keep.push_back("poses.frame");
      std::vector<std::vector<cognitive::Track>> tracks;
      std::vector<Pose> poses;
      const double t0 = now_ms();
      g.run(graph::FrameSource::recorded(input), o, [&](graph::FrameResult&& r) {
        tracks.push_back(r.outputs.at("tracks.tracks").get<std::vector<cognitive::Track>>());
        if (s == &estimated) poses.push_back(*r.outputs.at("poses.frame").get<Frame>().pose);
      });
      s->ms.push_back((now_ms() - t0) / frames);
      std::vector<Pose> world_from_track;
      if (s == &estimated) {
        // the odometry's world is the first camera: each frame's tracks are placed in the truth's
        // world through that frame's camera (what is reported is where the tracks are relative to
        // the current camera; drift then shows as misplaced tracks, not as a shifted world)
        for (std::size_t k = 0; k < seq.size(); ++k)
          world_from_track.push_back(seq[k].truth.camera_pose * poses[k].inverse());
        for (std::size_t k = 1; k < poses.size(); ++k) {
          const Pose truth = seq[k - 1].truth.camera_pose.inverse() * seq[k].truth.camera_pose;
          const Pose est = poses[k - 1].inverse() * poses[k];
          const Pose err = truth.inverse() * est;
          s->drift_mm.push_back(1000 * err.translation().norm());
          s->drift_deg.push_back(Eigen::AngleAxisd(err.linear()).angle() * 180 / M_PI);
        }
      }
      bench::score_sequence(seq, tracks, "seed " + std::to_string(seed), s->score, world_from_track);
    }
  }
  std::printf("bench_tracking: %d sequences (seeds 700-%d) of %d frames, rings leaning on jars\n\n", sequences,
              700 + sequences - 1, frames);
  std::printf("%-20s %10s %14s %10s %12s %14s %14s\n", "poses", "ms/frame", "false mugs", "dropped<=5",
              "mugs lost", "switches/100", "radius mm 1|10");
  auto line = [](const Setting& s) {
    const auto& c = s.score;
    std::printf("%-20s %10.1f %14d %10.3f %8d/%-3d %14.2f %8.3f|%.3f\n", s.name.c_str(), median(s.ms), c.false_mugs,
                c.false_mugs ? double(c.false_mugs_dropped_in_5) / c.false_mugs : 1.0, c.true_mugs_lost, c.true_mugs,
                c.mug_frames ? 100.0 * c.id_switches / c.mug_frames : 0.0, median(c.single_view_radius_mm),
                median(c.fused_radius_mm));
  };
  line(given);
  line(estimated);
  std::printf("\nodometry error per frame (against the true relative motion): median %.2f mm, %.3f deg; max %.1f mm\n",
              median(estimated.drift_mm), median(estimated.drift_deg),
              estimated.drift_mm.empty() ? 0.0 : *std::max_element(estimated.drift_mm.begin(), estimated.drift_mm.end()));
  for (const auto* s : {&given, &estimated})
    for (const auto& n : s->score.notes) std::printf("  %s: %s\n", s->name.c_str(), n.c_str());
  auto json = [](const Setting& s) {
    const auto& c = s.score;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "{\"ms_per_frame\": %.1f, \"false_mugs\": %d, \"false_dropped_within_5\": %.4f, \"true_mugs\": %d, "
                  "\"true_mugs_lost\": %d, \"id_switches_per_100\": %.3f, \"radius_mm_one_view\": %.4f, "
                  "\"radius_mm_after_10\": %.4f}",
                  median(s.ms), c.false_mugs, c.false_mugs ? double(c.false_mugs_dropped_in_5) / c.false_mugs : 1.0,
                  c.true_mugs, c.true_mugs_lost, c.mug_frames ? 100.0 * c.id_switches / c.mug_frames : 0.0,
                  median(c.single_view_radius_mm), median(c.fused_radius_mm));
    return std::string(buf);
  };
  std::printf("{\"bench\": \"tracking\", \"quick\": %s, \"sequences\": %d, \"frames\": %d, \"given\": %s, "
              "\"odometry\": %s, \"odometry_median_mm\": %.3f, \"odometry_median_deg\": %.4f}\n",
              quick ? "true" : "false", sequences, frames, json(given).c_str(), json(estimated).c_str(),
              median(estimated.drift_mm), median(estimated.drift_deg));
  return 0;
}
