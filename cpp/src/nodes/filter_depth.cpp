// filter_depth: edge-preserving bilateral filter of the frame's depth (signal::filter_depth).
//
//   nodes:
//     - {name: smooth, kind: filter_depth, options: {radius: 2, sigma_depth: 0.004}}
//   edges:
//     - source.frame -> smooth.frame
#include "mereo/signal/depth_filter.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec filter_depth_node() {
  using graph::OptionType;
  const signal::DepthFilterOptions def;
  graph::NodeSpec s;
  s.kind = "filter_depth";
  s.doc = "The frame with its depth smoothed by an edge-preserving bilateral filter (depth jumps stay sharp).";
  s.inputs = {{"frame", "Frame", "an RGB-D frame"}};
  s.outputs = {{"frame", "Frame", "the same frame, depth (and its own cloud, if any) filtered"}};
  s.options = {
      {"radius", OptionType::Int, (long long)def.radius, 1, 10, {}, "window half-size, pixels"},
      {"sigma_space", OptionType::Double, def.sigma_space, 0.1, 20, {}, "spatial sigma, pixels"},
      {"sigma_depth", OptionType::Double, def.sigma_depth, 1e-5, 0.1, {}, "range sigma at 1 m, metres (grows with z^2)"},
      {"depth_change_factor", OptionType::Double, def.depth_change_factor, 1e-4, 1, {},
       "neighbours further than this times z are ignored"},
  };
  s.make = [](const graph::Options& o) {
    signal::DepthFilterOptions f;
    f.radius = int(o.get_int("radius"));
    f.sigma_space = o.get_double("sigma_space");
    f.sigma_depth = o.get_double("sigma_depth");
    f.depth_change_factor = o.get_double("depth_change_factor");
    return graph::NodeBody([f](graph::NodeContext& ctx) {
      ctx.output("frame", signal::filter_depth(ctx.input<Frame>("frame"), f));
    });
  };
  return s;
}

}  // namespace mereo::nodes
