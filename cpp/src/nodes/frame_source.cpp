// frame_source: where a run's frames enter the graph.
//
//   nodes:
//     - {name: source, kind: frame_source}
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec frame_source_node() {
  graph::NodeSpec s;
  s.kind = "frame_source";
  s.doc = "The frames of the run (a recorded sequence or a live queue), one per run step.";
  s.outputs = {{"frame", "Frame", "the RGB-D frame"}};
  s.is_source = true;
  s.make = [](const graph::Options&) { return graph::NodeBody([](graph::NodeContext&) {}); };
  return s;
}

}  // namespace mereo::nodes
