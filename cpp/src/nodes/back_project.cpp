// back_project: depth to an organized XYZ cloud (extension::back_project).
//
//   nodes:
//     - {name: cloud, kind: back_project}
//   edges:
//     - source.frame -> cloud.frame
#include "mereo/extension/projection.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec back_project_node() {
  graph::NodeSpec s;
  s.kind = "back_project";
  s.doc = "The frame's organized XYZ cloud (metres, camera frame, NaN where depth is missing).";
  s.inputs = {{"frame", "Frame", "an RGB-D frame"}};
  s.outputs = {{"cloud", "Cloud", "H x W x 3 points"}};
  s.make = [](const graph::Options&) {
    return graph::NodeBody([](graph::NodeContext& ctx) {
      ctx.output("cloud", extension::back_project(ctx.input<Frame>("frame")));
    });
  };
  return s;
}

}  // namespace mereo::nodes
