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
// The last line is one JSON object.
//
//   bench_pipeline            every set, 60 frames each, K = 4
//   bench_pipeline --quick    4 frames of each set (ctest)
//   options: --frames N, --in-flight K, --graph FILE, --set kinect|stereo|real (repeatable)
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
  const std::filesystem::path real = MEREO_REAL_DATA;
  if (!std::filesystem::is_directory(real)) {
    std::printf("set real: skipped (%s not found: the real frames sit beside a clone of the repository)\n\n",
                real.c_str());
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

/// A result without its timings (the part both modes must agree on).
std::string comparable(const std::string& result) {
  auto j = nlohmann::json::parse(result);
  j.erase("timing_ms");
  return j.dump();
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
  auto run = [&](graph::Mode mode, std::vector<std::string>& results, std::vector<double>* per_frame) {
    graph::RunOptions o;
    o.mode = mode;
    o.max_in_flight = in_flight;
    o.on_error = graph::ErrorPolicy::Skip;
    o.keep = {"result.result"};
    results.assign(frames, "");
    double last = now_ms();
    const double t0 = last;
    g.run(source, o, [&](graph::FrameResult&& r) {
      const double t = now_ms();
      if (per_frame) per_frame->push_back(t - last);
      last = t;
      if (mode == graph::Mode::Parallel) fig.rss.push_back(memory_mb("VmRSS:"));
      if (r.ok()) results[r.index] = comparable(r.outputs.at("result.result").get<std::string>());
      else results[r.index] = std::string("error: ") + r.error->what();
    });
    return now_ms() - t0;
  };
  {  // warm-up (thread pool, first allocations)
    graph::RunOptions o;
    o.mode = graph::Mode::Parallel;
    o.on_error = graph::ErrorPolicy::Skip;
    g.run(graph::FrameSource::recorded({pool[0]}), o);
  }
  std::vector<std::string> parallel, serial;
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

}  // namespace

int main(int argc, char** argv) {
  nodes::register_builtin();
  std::size_t frames = 60, in_flight = 4;
  bool quick = false;
  std::vector<std::string> sets;
  std::string graph_file = std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true, frames = 4;
    else if (a == "--frames" && i + 1 < argc) frames = std::stoul(argv[++i]);
    else if (a == "--in-flight" && i + 1 < argc) in_flight = std::stoul(argv[++i]);
    else if (a == "--graph" && i + 1 < argc) graph_file = argv[++i];
    else if (a == "--set" && i + 1 < argc) sets.push_back(argv[++i]);
    else {
      std::fprintf(stderr, "bench_pipeline: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (sets.empty()) sets = {"kinect", "stereo", "real"};
  const std::size_t distinct = quick ? 4 : 20;
  graph::Graph g = graph::Graph::load(graph_file);
  g.verify();
  std::printf("bench_pipeline: %s, %zu frames per set (preloaded), K = %zu, 2 modes\n\n", graph_file.c_str(), frames,
              in_flight);

  std::vector<SetFigures> figs;
  for (const auto& name : sets) {
    if (name != "kinect" && name != "stereo" && name != "real") {
      std::fprintf(stderr, "bench_pipeline: unknown set %s (kinect, stereo or real)\n", name.c_str());
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

  double early = 0, late = 0;
  if (!figs.empty() && !figs[0].rss.empty()) {
    const auto& rss = figs[0].rss;
    const std::size_t fifth = std::max<std::size_t>(1, rss.size() / 5);
    for (std::size_t i = 0; i < fifth; ++i) early = std::max(early, rss[i]);
    for (std::size_t i = rss.size() - fifth; i < rss.size(); ++i) late = std::max(late, rss[i]);
  }
  const double peak = memory_mb("VmHWM:");
  std::printf("\nmemory: peak %.0f MB (every set's preloaded frames included); set %s, parallel: resident in the first "
              "fifth of the run %.0f MB, in the last %.0f MB (growth %.1f MB)\n",
              peak, figs.empty() ? "-" : figs[0].name.c_str(), early, late, late - early);

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
  j["peak_mb"] = std::round(peak * 10) / 10, j["rss_growth_mb"] = std::round((late - early) * 100) / 100;
  std::printf("%s\n", j.dump().c_str());
  // both modes must give the same results: a difference is a bug, not a figure
  for (const auto& f : figs)
    if (f.mismatches) return 1;
  return 0;
}
