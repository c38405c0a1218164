// Test-only node kinds for the engine's tests, the graph benchmark and the Python tests (never
// in the library's list):
//  - identity: passes the frame on (no work: measures the engine's cost per node);
//  - checksum: a CPU-heavy, deterministic checksum of the frame's depth;
//  - fail_on_frame: passes the frame on, but throws on the frame with the given index.
// They work on frames of any C++ type F registered as the port type "Frame" whose member
// `depth` has data() (float values) and pixels() (mereo::Frame, or a test's own frame type).
//
//   mereo::test_nodes::register_test_nodes<mereo::Frame>();
//   nodes:
//     - {name: work, kind: checksum, options: {rounds: 20}}
//     - {name: broken, kind: fail_on_frame, options: {frame: 7}}
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "mereo/graph/node.hpp"

namespace mereo::test_nodes {

/// `rounds` passes of a floating-point hash over the positive values of depth[0, n).
inline double depth_checksum(const float* d, std::size_t n, long long rounds) {
  double acc = 0;
  for (long long r = 0; r < rounds; ++r) {
    double a = double(r) * 0.618;
    for (std::size_t i = 0; i < n; ++i)
      if (d[i] > 0) a = std::fmod(a * 1.000001 + d[i] * (1 + (i & 7)), 1e6);
    acc += a;
  }
  return acc;
}

inline graph::NodeSpec identity_node() {
  graph::NodeSpec s;
  s.kind = "identity";
  s.doc = "Passes the frame on unchanged (no work: measures the engine's cost per node).";
  s.inputs = {{"frame", "Frame", "any frame"}};
  s.outputs = {{"frame", "Frame", "the same frame"}};
  s.make = [](const graph::Options&) {
    return graph::NodeBody([](graph::NodeContext& ctx) { ctx.set_output("frame", ctx.input_value("frame")); });
  };
  return s;
}

template <typename F>
graph::NodeSpec checksum_node() {
  graph::NodeSpec s;
  s.kind = "checksum";
  s.doc = "A CPU-heavy, deterministic checksum of the frame's depth (engine benchmarks).";
  s.inputs = {{"frame", "Frame", "an RGB-D frame"}};
  s.outputs = {{"value", "Number", "the checksum"}};
  s.options = {{"rounds", graph::OptionType::Int, 1LL, 1, 1e6, {}, "passes over the image"}};
  s.make = [](const graph::Options& o) {
    const long long rounds = o.get_int("rounds");
    return graph::NodeBody([rounds](graph::NodeContext& ctx) {
      const auto& depth = ctx.input<F>("frame").depth;
      ctx.output("value", depth_checksum(depth.data(), depth.pixels(), rounds));
    });
  };
  return s;
}

inline graph::NodeSpec fail_on_frame_node() {
  graph::NodeSpec s;
  s.kind = "fail_on_frame";
  s.doc = "Passes the frame on, but throws on the frame with the given index (error-policy tests).";
  s.inputs = {{"frame", "Frame", "any frame"}};
  s.outputs = {{"frame", "Frame", "the same frame"}};
  s.options = {{"frame", graph::OptionType::Int, 0LL, 0, 1e12, {}, "index of the frame to fail on"}};
  s.make = [](const graph::Options& o) {
    const auto bad = std::size_t(o.get_int("frame"));
    return graph::NodeBody([bad](graph::NodeContext& ctx) {
      if (ctx.frame_index() == bad) throw std::runtime_error("failing on purpose on frame " + std::to_string(bad));
      ctx.set_output("frame", ctx.input_value("frame"));
    });
  };
  return s;
}

/// Registers identity, checksum and fail_on_frame once (the port type "Frame" must be F's).
template <typename F>
void register_test_nodes() {
  static const bool done = [] {
    graph::register_node(identity_node());
    graph::register_node(checksum_node<F>());
    graph::register_node(fail_on_frame_node());
    return true;
  }();
  (void)done;
}

}  // namespace mereo::test_nodes
