// filter_depth: edge-preserving bilateral filter of the frame's depth (signal::filter_depth).
//
//   nodes:
//     - {name: smooth, kind: filter_depth, options: {radius: 2, sigma_depth: 0.004}}
//   edges:
//     - source.frame -> smooth.frame
#include "mereo/signal/depth_filter.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec filter_depth_node() {
  graph::NodeSpec s;
  s.kind = "filter_depth";
  s.doc = "The frame with its depth smoothed by an edge-preserving bilateral filter (depth jumps stay sharp).";
  s.inputs = {{"frame", "Frame", "an RGB-D frame"}};
  s.outputs = {{"frame", "Frame", "the same frame, depth (and its own cloud, if any) filtered"}};
  s.options = options_of<signal::DepthFilterOptions>();
  s.make = [](const graph::Options& o) {
    const auto f = options_from<signal::DepthFilterOptions>(o);
    return graph::NodeBody([f](graph::NodeContext& ctx) {
      ctx.output("frame", signal::filter_depth(ctx.input<Frame>("frame"), f));
    });
  };
  return s;
}

}  // namespace mereo::nodes
