// detect_edges: the edge modality's segments, lines and elliptical arcs of the colour image
// (features::fit_edge_primitives on signal::detect_edges' chains), lifted to 3-D with the cloud
// where it has depth.
//
//   nodes:
//     - {name: edges, kind: detect_edges, options: {gradient_threshold: 24, min_arc_span_deg: 60}}
//   edges:
//     - source.frame -> edges.frame
//     - cloud.cloud -> edges.cloud        # optional: lift the lines and arcs to 3-D
#include "mereo/core/error.hpp"
#include "mereo/features/edges.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec detect_edges_node() {
  graph::NodeSpec s;
  s.kind = "detect_edges";
  s.doc = "Lines and elliptical arcs of the frame's colour image, with their side colours; 3-D where the cloud has depth.";
  s.inputs = {{"frame", "Frame", "a frame with a colour image"},
              {"cloud", "Cloud", "its organized cloud: the lines and arcs are lifted to 3-D", false}};
  s.outputs = {{"segments", "Segments", "arcs, then lines (classes arc and line)"}};
  s.options = options_of<features::EdgePrimitiveOptions>();
  s.make = [](const graph::Options& o) {
    const auto eo = options_from<features::EdgePrimitiveOptions>(o);
    return graph::NodeBody([eo](graph::NodeContext& ctx) {
      const Frame& f = ctx.input<Frame>("frame");
      if (f.color.empty()) throw InputError(f.source + ": detect_edges needs a colour image");
      const auto chains = signal::detect_edges(f.color, eo.edges);
      const Cloud* cloud = ctx.has_input("cloud") ? &ctx.input<Cloud>("cloud") : nullptr;
      ctx.output("segments", features::fit_edge_primitives(chains, f.color, cloud, eo));
    });
  };
  return s;
}

}  // namespace mereo::nodes
