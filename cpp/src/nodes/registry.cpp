#include "nodes/registry.hpp"

#include "mereo/nodes/builtin.hpp"

namespace mereo::nodes {

std::vector<graph::NodeSpec> builtin_node_specs() {
  return {
      frame_source_node(),
      filter_depth_node(),
      back_project_node(),
      estimate_normals_node(),
      support_plane_node(),
      detect_primitives_node(),
      detect_edges_node(),
      find_regions_node(),
      detect_patches_node(),
      detect_legs_node(),
      models_node(),
      match_models_node(),
      interpret_node(),
      odometry_node(),
      track_objects_node(),
      report_node(),
  };
}

void register_builtin() {
  // Once per process; a concurrent caller waits until it is done (a function-local static).
  static const bool done = [] {
    register_port_types();
    for (auto& s : builtin_node_specs()) graph::register_node(std::move(s));
    return true;
  }();
  (void)done;
}

}  // namespace mereo::nodes
