// bench_pipeline: the tabletop pipeline (graphs/tabletop.yaml) over preloaded VGA frames, in
// parallel mode (oneTBB flow graph, K frames in flight) and in deterministic mode, with per-node
// timings, and the process's resident memory sampled after every frame: its peak, and its
// growth between the first and the last fifth of the run (a leak would make it grow with the
// number of frames).
//
// The frames are rendered once (20 distinct noisy synthetic scenes, seeds 500-519) and the
// source hands out copies of them in turn, so that the run measures the graph, not rendering.
// The reference of the ratio is the same graph run one frame at a time (deterministic mode).
// The last line is one JSON object.
//
//   bench_pipeline            100 frames, K = 4
//   bench_pipeline --quick    12 frames (ctest)
//   options: --frames N, --in-flight K, --graph FILE (another pipeline file)
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "mereo/graph/graph.hpp"
#include "mereo/nodes/builtin.hpp"
#include "mereo/synthetic/scene.hpp"

using namespace mereo;
using bench::now_ms;

namespace {

/// Resident memory of this process, MB (Linux /proc).
double rss_mb() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

/// Peak resident memory of this process so far, MB.
double peak_mb() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  nodes::register_builtin();
  int frames = 100, in_flight = 4;
  bool quick = false;
  std::string graph_file = std::string(MEREO_SOURCE_DIR) + "/graphs/tabletop.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true, frames = 12;
    else if (a == "--frames" && i + 1 < argc) frames = std::stoi(argv[++i]);
    else if (a == "--in-flight" && i + 1 < argc) in_flight = std::stoi(argv[++i]);
    else if (a == "--graph" && i + 1 < argc) graph_file = argv[++i];
  }
  const int distinct = quick ? 4 : 20;
  std::vector<Frame> pool;
  for (int s = 0; s < distinct; ++s) pool.push_back(synthetic::render(std::uint64_t(500 + s)).frame);
  const auto source = graph::FrameSource::from_function(std::size_t(frames), [&](std::size_t i) {
    Frame f = pool[i % pool.size()];
    f.id = std::to_string(i);
    return f;
  });
  graph::Graph g = graph::Graph::load(graph_file);
  g.verify();

  auto run = [&](graph::Mode mode, std::vector<double>* rss, std::size_t* objects) {
    graph::RunOptions o;
    o.mode = mode;
    o.max_in_flight = std::size_t(in_flight);
    o.keep = {"result.result"};
    const double t0 = now_ms();
    g.run(source, o, [&](graph::FrameResult&& r) {
      if (rss) rss->push_back(rss_mb());
      if (objects) *objects += r.outputs.at("result.result").get<std::string>().size() > 0;
    });
    return now_ms() - t0;
  };
  // warm-up (thread pool, first allocations), then the runs
  {
    graph::RunOptions o;
    o.mode = graph::Mode::Parallel;
    g.run(graph::FrameSource::recorded({pool[0]}), o);
  }
  std::vector<double> rss;
  std::size_t results = 0;
  const double parallel_ms = run(graph::Mode::Parallel, &rss, &results);
  const auto timings = g.last_summary().timings;
  const double serial_ms = run(graph::Mode::Deterministic, nullptr, nullptr);
  const double fps = 1000.0 * frames / parallel_ms, fps_serial = 1000.0 * frames / serial_ms;

  const std::size_t fifth = std::max<std::size_t>(1, rss.size() / 5);
  double early = 0, late = 0;
  for (std::size_t i = 0; i < fifth; ++i) early = std::max(early, rss[i]);
  for (std::size_t i = rss.size() - fifth; i < rss.size(); ++i) late = std::max(late, rss[i]);

  std::printf("bench_pipeline: %s, %d VGA frames (%d distinct, preloaded), K = %d\n\n", graph_file.c_str(), frames,
              distinct, in_flight);
  std::printf("%-14s %8s %10s %10s %10s\n", "node", "count", "mean ms", "median ms", "max ms");
  for (const auto& t : timings)
    std::printf("%-14s %8zu %10.2f %10.2f %10.2f\n", t.node.c_str(), t.count, t.mean_ms, t.median_ms, t.max_ms);
  std::printf("\nparallel: %.1f frames/s (%.1f ms per frame); one frame at a time: %.1f frames/s; ratio %.2f\n", fps,
              parallel_ms / frames, fps_serial, fps / fps_serial);
  std::printf("memory: peak %.0f MB (the %d preloaded frames included); resident in the first fifth of the run "
              "%.0f MB, in the last %.0f MB (growth %.1f MB)\n",
              peak_mb(), distinct, early, late, late - early);
  std::printf("{\"bench\": \"pipeline\", \"quick\": %s, \"frames\": %d, \"in_flight\": %d, \"fps\": %.2f, "
              "\"fps_one_at_a_time\": %.2f, \"speedup\": %.3f, \"peak_mb\": %.1f, \"rss_first_fifth_mb\": %.1f, "
              "\"rss_last_fifth_mb\": %.1f, \"rss_growth_mb\": %.2f, \"results\": %zu}\n",
              quick ? "true" : "false", frames, in_flight, fps, fps_serial, fps / fps_serial, peak_mb(), early, late,
              late - early, results);
  return 0;
}
