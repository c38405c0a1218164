// Diagnostic nodes for the engine's tests and benchmarks: identity (no work, measures the
// engine's own cost), checksum (CPU-heavy, deterministic), fail_on_frame (throws on purpose).
//
//   nodes:
//     - {name: work, kind: checksum, options: {rounds: 20}}
//     - {name: broken, kind: fail_on_frame, options: {frame: 7}}
#include <cmath>
#include <stdexcept>

#include "mereo/core/frame.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec identity_node() {
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

/// A deterministic, CPU-heavy function of a depth image: `rounds` passes of a
/// floating-point hash over every valid pixel.
double depth_checksum(const DepthImage& depth, long long rounds) {
  double acc = 0;
  for (long long r = 0; r < rounds; ++r) {
    double a = double(r) * 0.618;
    const float* d = depth.data();
    for (std::size_t i = 0; i < depth.pixels(); ++i)
      if (d[i] > 0) a = std::fmod(a * 1.000001 + d[i] * (1 + (i & 7)), 1e6);
    acc += a;
  }
  return acc;
}

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
      ctx.output("value", depth_checksum(ctx.input<Frame>("frame").depth, rounds));
    });
  };
  return s;
}

graph::NodeSpec fail_on_frame_node() {
  graph::NodeSpec s;
  s.kind = "fail_on_frame";
  s.doc = "Passes the frame on, but throws on the frame with the given index (error-policy tests).";
  s.inputs = {{"frame", "Frame", "any frame"}};
  s.outputs = {{"frame", "Frame", "the same frame"}};
  s.options = {{"frame", graph::OptionType::Int, 0LL, 0, 1e12, {}, "index of the frame to fail on"}};
  s.make = [](const graph::Options& o) {
    const auto bad = std::size_t(o.get_int("frame"));
    return graph::NodeBody([bad](graph::NodeContext& ctx) {
      if (ctx.frame_index() == bad)
        throw std::runtime_error("failing on purpose on frame " + std::to_string(bad));
      ctx.set_output("frame", ctx.input_value("frame"));
    });
  };
  return s;
}

}  // namespace mereo::nodes
