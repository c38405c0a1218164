// bench_pipeline: the tabletop pipeline (graphs/tabletop.yaml) over preloaded frames, per frame
// set: in parallel mode (oneTBB flow graph, K frames in flight) and in deterministic mode (one
// frame at a time, the reference of the ratio), the per-node medians, whether both modes gave
// the same results, and the process's resident memory sampled after every frame of the first
// set: its peak, and its growth between the first and the last fifth of the run (a leak would
// make it grow with the number of frames).
//
// Frame sets (each loaded once; the source hands out copies in turn, so that the run measures
// the graph, not rendering or decoding):
//   kinect   rendered tabletop scenes, seeds 500-519, the Kinect-like depth model
//   stereo   the same scenes with the active-stereo depth model
//   real     the real tabletop frames of ../shared/data/real (nv-6dof-graspnet, posecnn,
//            pcl-mosd, the PCL mug); skipped with a message when that folder is absent
//   room     rendered rooms (SceneOptions::room, seeds 9300-9319), for graphs/room.yaml
//   room_real  the real rooms: nvblox-3dmatch's seq-01, pcl-pairwise and PCL's office1
// The last line is one JSON object.
//
// --growth: how the cost grows instead, on rendered Kinect-like scenes (seeds 600-609): against
// the number of objects on the table (1 to 20, VGA) and against the image size (QVGA, VGA,
// 1280x720 with the focal length scaled, 3-6 objects); scripts/growth_plot.py draws its JSON.
// Memory: resident memory after every frame of the first set, from frame 50 on (a run of 1000
// frames: --frames 1000 --set kinect) must stay flat.
//
//   bench_pipeline            every set, 60 frames each, K = 4
//   bench_pipeline --quick    4 frames of each set (ctest)
//   bench_pipeline --growth   the growth tables (20 frames per point)
//   options: --frames N, --in-flight K, --graph FILE, --set kinect|stereo|real|room|room_real
//   (repeatable); the room graph: --graph graphs/room.yaml --set room --set room_real
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_util.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/io/io.hpp"
#include "mereo/nodes/builtin.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
using bench::now_ms;

namespace {

/// Resident memory of this process, MB (Linux /proc); `field` VmRSS (now) or VmHWM (peak).
double memory_mb(const char* field) {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(std::string(field).size())) / 1024.0;
  return 0.0;
}

/// The frames of one set, or none (with the reason printed) when its data is absent.
std::vector<Frame> load_set(const std::string& name, std::size_t distinct) {
  std::vector<Frame> pool;
  if (name == "kinect" || name == "stereo") {
    synthetic::SceneOptions so;
    so.depth_model = name == "kinect" ? synthetic::DepthModel::Kinect : synthetic::DepthModel::Stereo;
    for (std::size_t s = 0; s < distinct; ++s) pool.push_back(synthetic::render(500 + s, so).frame);
    return pool;
  }
  if (name == "room") {  // rendered rooms (Kinect-like), for the room graph
    synthetic::SceneOptions so;
    so.room = true;
    for (std::size_t s = 0; s < distinct; ++s) pool.push_back(synthetic::render(9300 + s, so).frame);
    return pool;
  }
  const std::filesystem::path real = MEREO_REAL_DATA;
  if (!std::filesystem::is_directory(real)) {
    std::printf("set real: skipped (%s not found: the real frames sit beside a clone of the repository)\n\n",
                real.c_str());
    return pool;
  }
  if (name == "room_real") {  // real rooms: 3DMatch (its layout names the camera), pcl-pairwise, office1
    for (const auto& seq : {io::open({(real / "nvblox-3dmatch" / "seq-01").string()}),
                            io::open({(real / "pcl-pairwise").string(), (real / "pcl" / "office1.pcd").string()})})
      for (std::size_t i = 0; i < seq.size(); ++i) pool.push_back(seq.load(i));
    return pool;
  }
  io::ReadOptions posecnn;  // PoseCNN's camera (its SOURCE.md), depth in 0.1 mm
  posecnn.intrinsics = Intrinsics{1066.778, 1067.487, 312.9869, 241.3109};
  posecnn.depth_scale = 10000.0;
  const std::vector<io::Sequence> seqs = {
      io::open({(real / "nv-6dof-graspnet").string()}), io::open({(real / "posecnn").string()}, posecnn),
      io::open({(real / "pcl-mosd").string(), (real / "pcl" / "table_scene_mug_stereo_textured.pcd").string()})};
  // every frame, or (--quick) the first of each folder
  for (const auto& seq : seqs)
    for (std::size_t i = 0; i < seq.size() && (i == 0 || distinct > 4); ++i) pool.push_back(seq.load(i));
  return pool;
}

/// One point of the growth tables: rendered Kinect-like scenes with `objects` objects (0: the
/// renderer's 3-6) in a width x height image whose focal length scales with the width.
std::vector<Frame> growth_set(int objects, int width, int height, std::size_t distinct) {
  synthetic::SceneOptions so;
  if (objects > 0) so.min_objects = so.max_objects = objects;
  const double scale = double(width) / 640.0;
  so.width = width, so.height = height;
  so.intrinsics = Intrinsics{525.0 * scale, 525.0 * scale, 0.5 * width - 0.5, 0.5 * height - 0.5};
  std::vector<Frame> pool;
  for (std::size_t s = 0; s < distinct; ++s) pool.push_back(synthetic::render(600 + s, so).frame);
  return pool;
}

/// A result without its timings (the part both modes must agree on), hashed: a run of 1000
/// frames would otherwise hold 1000 results, and its memory figure would measure them.
std::size_t comparable(const std::string& result) {
  auto j = nlohmann::json::parse(result);
  j.erase("timing_ms");
  return std::hash<std::string>{}(j.dump());
}

struct SetFigures {
  std::string name;
  std::size_t distinct = 0, frames = 0, mismatches = 0;
  double fps = 0, fps_one_at_a_time = 0, median_one_at_a_time_ms = 0;
  std::vector<graph::NodeTiming> timings;  // deterministic mode: a stage's own time
  std::vector<double> rss;
};

SetFigures run_set(graph::Graph& g, const std::string& name, std::vector<Frame> pool, std::size_t frames,
                   std::size_t in_flight) {
  SetFigures fig;
  fig.name = name, fig.distinct = pool.size(), fig.frames = frames;
  const auto source = graph::FrameSource::from_function(frames, [&](std::size_t i) {
    Frame f = pool[i % pool.size()];
    f.id = std::to_string(i);
    return f;
  });
  auto run = [&](graph::Mode mode, std::vector<std::size_t>& results, std::vector<double>* per_frame) {
    graph::RunOptions o;
    o.mode = mode;
    o.max_in_flight = in_flight;
    o.on_error = graph::ErrorPolicy::Skip;
    o.keep = {"result.result"};
    results.assign(frames, 0);
    double last = now_ms();
    const double t0 = last;
    g.run(source, o, [&](graph::FrameResult&& r) {
      const double t = now_ms();
      if (per_frame) per_frame->push_back(t - last);
      last = t;
      if (mode == graph::Mode::Parallel) fig.rss.push_back(memory_mb("VmRSS:"));
      if (r.ok()) results[r.index] = comparable(r.outputs.at("result.result").get<std::string>());
      else results[r.index] = std::hash<std::string>{}(std::string("error: ") + r.error->what());
    });
    return now_ms() - t0;
  };
  {  // warm-up (thread pool, first allocations)
    graph::RunOptions o;
    o.mode = graph::Mode::Parallel;
    o.on_error = graph::ErrorPolicy::Skip;
    g.run(graph::FrameSource::recorded({pool[0]}), o);
  }
  std::vector<std::size_t> parallel, serial;
  std::vector<double> per_frame;
  const double parallel_ms = run(graph::Mode::Parallel, parallel, nullptr);
  const double serial_ms = run(graph::Mode::Deterministic, serial, &per_frame);
  fig.timings = g.last_summary().timings;
  fig.fps = 1000.0 * double(frames) / parallel_ms;
  fig.fps_one_at_a_time = 1000.0 * double(frames) / serial_ms;
  fig.median_one_at_a_time_ms = bench::median(per_frame);
  for (std::size_t i = 0; i < frames; ++i) fig.mismatches += parallel[i] != serial[i];
  return fig;
}

/// A stage's median in one set's figures (NAN when the graph has no such node).
double stage_ms(const SetFigures& f, const std::string& node) {
  for (const auto& t : f.timings)
    if (t.node == node) return t.median_ms;
  return NAN;
}

/// The growth tables (--growth): one row per point, the whole frame and its main stages.
int run_growth(graph::Graph& g, std::size_t frames, std::size_t distinct, std::size_t in_flight) {
  const std::vector<std::string> stages = {"filter", "normals", "table", "primitives"};
  struct Point {
    std::string axis;
    int objects, width, height;
  };
  std::vector<Point> points;
  for (int n : {1, 2, 5, 10, 15, 20}) points.push_back({"objects", n, 640, 480});
  for (auto [w, h] : {std::pair{320, 240}, {640, 480}, {1280, 720}}) points.push_back({"size", 0, w, h});
  nlohmann::json j;
  j["bench"] = "pipeline_growth", j["frames_per_point"] = frames, j["in_flight"] = in_flight;
  bool same = true;
  std::string axis;
  for (const auto& p : points) {
    if (p.axis != axis) {
      axis = p.axis;
      std::printf("\n%s\n%-12s %9s %9s %10s",
                  axis == "objects" ? "objects on the table (VGA)" : "image size (3-6 objects)",
                  axis == "objects" ? "objects" : "size", "frames/s", "ms/frame", "one at a");
      for (const auto& st : stages) std::printf(" %10s", st.c_str());
      std::printf(" %8s\n", "rest");
    }
    const SetFigures f = run_set(g, axis, growth_set(p.objects, p.width, p.height, distinct), frames, in_flight);
    same = same && f.mismatches == 0;
    const std::string label =
        axis == "objects" ? std::to_string(p.objects) : std::to_string(p.width) + "x" + std::to_string(p.height);
    std::printf("%-12s %9.1f %9.1f %10.1f", label.c_str(), f.fps, 1000.0 / f.fps, f.median_one_at_a_time_ms);
    double rest = f.median_one_at_a_time_ms;
    nlohmann::json row = {{"objects", p.objects}, {"width", p.width}, {"height", p.height},
                          {"fps", std::round(f.fps * 100) / 100},
                          {"median_ms", std::round(f.median_one_at_a_time_ms * 100) / 100},
                          {"same_results", f.frames - f.mismatches}};
    for (const auto& st : stages) {
      const double ms = stage_ms(f, st);
      std::printf(" %10.1f", ms);
      rest -= std::isnan(ms) ? 0.0 : ms;
      row["stage_median_ms"][st] = std::round(ms * 100) / 100;
    }
    std::printf(" %8.1f\n", std::max(0.0, rest));
    j[axis].push_back(row);
  }
  std::printf("\n(ms/frame: 1000 / frames per second in parallel mode; one at a time: the median frame in "
              "deterministic mode, whose stages are the columns after it; rest: matching, regions, result)\n%s\n",
              j.dump().c_str());
  return same ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  nodes::register_builtin();
  std::size_t frames = 0, in_flight = 4;  // (frames: 60, 4 with --quick, 20 per point with --growth)
  bool quick = false, growth = false;
  std::vector<std::string> sets;
  std::string graph_file = std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--growth") growth = true;
    else if (a == "--frames" && i + 1 < argc) frames = std::stoul(argv[++i]);
    else if (a == "--in-flight" && i + 1 < argc) in_flight = std::stoul(argv[++i]);
    else if (a == "--graph" && i + 1 < argc) graph_file = argv[++i];
    else if (a == "--set" && i + 1 < argc) sets.push_back(argv[++i]);
    else {
      std::fprintf(stderr, "bench_pipeline: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (frames == 0) frames = quick ? 4 : growth ? 20 : 60;
  if (sets.empty()) sets = {"kinect", "stereo", "real"};
  const std::size_t distinct = quick ? 4 : 20;
  graph::Graph g = graph::Graph::load(graph_file);
  g.verify();
  if (growth) {
    const std::size_t scenes = quick ? 2 : 10;
    std::printf("bench_pipeline --growth: %s, %zu frames per point (%zu scenes), K = %zu\n", graph_file.c_str(), frames,
                scenes, in_flight);
    return run_growth(g, frames, scenes, in_flight);
  }
  std::printf("bench_pipeline: %s, %zu frames per set (preloaded), K = %zu, 2 modes\n\n", graph_file.c_str(), frames,
              in_flight);

  std::vector<SetFigures> figs;
  for (const auto& name : sets) {
    if (name != "kinect" && name != "stereo" && name != "real" && name != "room" && name != "room_real") {
      std::fprintf(stderr, "bench_pipeline: unknown set %s (kinect, stereo, real, room or room_real)\n", name.c_str());
      return 2;
    }
    auto pool = load_set(name, distinct);
    if (pool.empty()) continue;
    figs.push_back(run_set(g, name, std::move(pool), frames, in_flight));
  }

  // per-stage medians (deterministic mode: each stage's own time), one column per set
  std::map<std::string, std::vector<double>> stage;
  std::vector<std::string> order;
  for (std::size_t k = 0; k < figs.size(); ++k)
    for (const auto& t : figs[k].timings) {
      if (!stage.count(t.node)) order.push_back(t.node), stage[t.node].assign(figs.size(), NAN);
      stage[t.node][k] = t.median_ms;
    }
  std::printf("%-22s", "median ms per frame");
  for (const auto& f : figs) std::printf(" %10s", f.name.c_str());
  std::printf("\n");
  for (const auto& node : order) {
    std::printf("%-22s", node.c_str());
    for (double ms : stage[node]) std::printf(" %10.2f", ms);
    std::printf("\n");
  }
  std::printf("%-22s", "whole frame");
  for (const auto& f : figs) std::printf(" %10.1f", f.median_one_at_a_time_ms);
  std::printf("\n\n%-8s %9s %12s %19s %7s %22s\n", "set", "frames", "frames/s", "one at a time f/s", "ratio",
              "same results (of N)");
  for (const auto& f : figs)
    std::printf("%-8s %4zu (%2zu) %12.1f %19.1f %7.2f %17zu/%zu\n", f.name.c_str(), f.frames, f.distinct, f.fps,
                f.fps_one_at_a_time, f.fps / f.fps_one_at_a_time, f.frames - f.mismatches, f.frames);

  // resident memory once the first frames have settled it (frame 50, or the first fifth of a
  // shorter run), and the highest after that: a leak grows it with the number of frames
  double settled = 0, highest = 0;
  std::size_t settle = 0;
  if (!figs.empty() && !figs[0].rss.empty()) {
    const auto& rss = figs[0].rss;
    settle = std::max<std::size_t>(1, std::min<std::size_t>(50, rss.size() / 5));
    settled = rss[settle - 1];
    for (std::size_t i = settle; i < rss.size(); ++i) highest = std::max(highest, rss[i]);
    highest = std::max(highest, settled);
  }
  const double peak = memory_mb("VmHWM:");
  std::printf("\nmemory: peak %.0f MB (every set's preloaded frames included); set %s, parallel: resident after frame "
              "%zu %.0f MB, highest after it %.0f MB (growth %.1f MB over %zu frames)\n",
              peak, figs.empty() ? "-" : figs[0].name.c_str(), settle, settled, highest, highest - settled,
              figs.empty() ? std::size_t(0) : figs[0].rss.size() - settle);
  // the trend: mean resident memory over the 100 frames after frame 50 and over the last 100
  // (the highest single value swings with the frames in flight)
  double trend = NAN;
  if (!figs.empty() && figs[0].rss.size() >= 250) {
    const auto& rss = figs[0].rss;
    double a = 0, b = 0;
    for (std::size_t i = 50; i < 150; ++i) a += rss[i] / 100;
    for (std::size_t i = rss.size() - 100; i < rss.size(); ++i) b += rss[i] / 100;
    trend = b - a;
    std::printf("mean resident over frames 51-150 %.0f MB, over the last 100 %.0f MB (trend %+.1f MB)\n", a, b, trend);
  }
  if (!figs.empty() && figs[0].rss.size() >= 100) {
    std::printf("resident (MB) after frame");
    for (std::size_t n = 50; n <= figs[0].rss.size(); n *= 2) std::printf("  %zu: %.0f", n, figs[0].rss[n - 1]);
    std::printf("  %zu: %.0f\n", figs[0].rss.size(), figs[0].rss.back());
  }

  nlohmann::json j;
  j["bench"] = "pipeline", j["quick"] = quick, j["frames_per_set"] = frames, j["in_flight"] = in_flight;
  for (const auto& f : figs) {
    auto& s = j["sets"][f.name];
    s["distinct"] = f.distinct, s["fps"] = std::round(f.fps * 100) / 100;
    s["fps_one_at_a_time"] = std::round(f.fps_one_at_a_time * 100) / 100;
    s["median_ms"] = std::round(f.median_one_at_a_time_ms * 100) / 100;
    s["same_results"] = f.frames - f.mismatches;
    for (const auto& t : f.timings) s["stage_median_ms"][t.node] = std::round(t.median_ms * 100) / 100;
  }
  j["peak_mb"] = std::round(peak * 10) / 10, j["rss_growth_mb"] = std::round((highest - settled) * 100) / 100;
  if (!std::isnan(trend)) j["rss_trend_mb"] = std::round(trend * 100) / 100;
  std::printf("%s\n", j.dump().c_str());
  // both modes must give the same results: a difference is a bug, not a figure
  for (const auto& f : figs)
    if (f.mismatches) return 1;
  return 0;
}
