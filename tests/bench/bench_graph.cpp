// The engine's benchmark: (1) a graph of three independent CPU-heavy nodes over 100 VGA
// frames in deterministic and parallel mode (speed-up on this machine), (2) the engine's
// own cost per node per frame, with empty (identity) nodes. Last line: one JSON object.
//   bench_graph [--quick]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "mereo/graph/graph.hpp"
#include "mereo/nodes/builtin.hpp"
#include "mereo/synthetic/scene.hpp"
#include "support/test_nodes.hpp"

using namespace mereo;
using namespace mereo::graph;
using Clock = std::chrono::steady_clock;

namespace {

double run_ms(Graph& g, const FrameSource& src, Mode mode, std::size_t in_flight = 4) {
  RunOptions o;
  o.mode = mode;
  o.max_in_flight = in_flight;
  const auto t0 = Clock::now();
  std::size_t n = 0;
  g.run(src, o, [&](FrameResult&&) { ++n; });
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const int frames = quick ? 12 : 100;
  const int repeats = quick ? 1 : 3;
  const unsigned cores = std::thread::hardware_concurrency();
  nodes::register_builtin();
  test_nodes::register_test_nodes<Frame>();  // identity and checksum

  // Frames: a few rendered VGA frames, repeated (the engine, not the renderer, is measured).
  std::vector<Frame> distinct;
  for (auto& sf : synthetic::render_sequence(5, 4)) distinct.push_back(sf.frame);
  auto source = FrameSource::from_function(frames, [&](std::size_t i) { return distinct[i % distinct.size()]; });

  // (1) three independent CPU-heavy nodes.
  Graph heavy;
  heavy.add("frame_source", "source");
  for (const char* name : {"a", "b", "c"}) {
    heavy.add("checksum", name, {{"rounds", 6LL}});
    heavy.connect(std::string("source.frame"), std::string(name) + ".frame");
  }
  double det = 1e300, par = 1e300;
  for (int r = 0; r < repeats; ++r) {
    det = std::min(det, run_ms(heavy, source, Mode::Deterministic));
    par = std::min(par, run_ms(heavy, source, Mode::Parallel));
  }
  const auto timings = heavy.last_summary().timings;
  std::printf("three independent checksum nodes, %d VGA frames, %u cores (best of %d)\n", frames, cores, repeats);
  std::printf("  %-14s %10s %12s\n", "mode", "total ms", "ms / frame");
  std::printf("  %-14s %10.1f %12.2f\n", "deterministic", det, det / frames);
  std::printf("  %-14s %10.1f %12.2f\n", "parallel", par, par / frames);
  std::printf("  speed-up parallel / deterministic: %.2fx\n", det / par);
  std::printf("  per-node timings of the last (parallel) run:\n");
  for (const auto& t : timings)
    std::printf("    %-4s count %zu  mean %.2f ms  median %.2f ms  max %.2f ms\n", t.node.c_str(), t.count, t.mean_ms,
                t.median_ms, t.max_ms);

  // (2) the engine's own cost: 20 identity nodes in a chain over many small frames, minus
  // the cost of a graph with the source alone.
  const int n_nodes = 20, small_frames = quick ? 500 : 5000;
  Frame tiny;
  tiny.depth = DepthImage(2, 2, 1.0f);
  auto tiny_source = FrameSource::from_function(small_frames, [&](std::size_t) { return tiny; });
  Graph empty;
  empty.add("frame_source", "source");
  empty.add("identity", "n0");
  empty.connect("source.frame", "n0.frame");
  Graph chain;
  chain.add("frame_source", "source");
  std::string prev = "source";
  for (int i = 0; i < n_nodes; ++i) {
    const std::string name = "n" + std::to_string(i);
    chain.add("identity", name);
    chain.connect(prev + ".frame", name + ".frame");
    prev = name;
  }
  nlohmann::json overhead;
  std::printf("engine cost per node per frame (%d identity nodes in a chain, %d frames)\n", n_nodes, small_frames);
  for (Mode mode : {Mode::Deterministic, Mode::Parallel}) {
    double base = 1e300, full = 1e300;
    for (int r = 0; r < repeats + 1; ++r) {
      base = std::min(base, run_ms(empty, tiny_source, mode));
      full = std::min(full, run_ms(chain, tiny_source, mode));
    }
    const double us = (full - base) * 1000.0 / (double(small_frames) * (n_nodes - 1));
    const char* name = mode == Mode::Parallel ? "parallel" : "deterministic";
    std::printf("  %-14s %.2f us\n", name, us);
    overhead[name] = us;
  }

  nlohmann::json out = {{"benchmark", "graph"},
                        {"cores", cores},
                        {"frames", frames},
                        {"deterministic_ms", det},
                        {"parallel_ms", par},
                        {"speedup", det / par},
                        {"engine_us_per_node_frame", overhead}};
  std::printf("%s\n", out.dump().c_str());
  return 0;
}
