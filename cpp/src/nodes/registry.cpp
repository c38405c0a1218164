#include "nodes/registry.hpp"

namespace mereo::nodes {

std::vector<graph::NodeSpec> builtin_node_specs() {
  return {
      frame_source_node(),
      filter_depth_node(),
      back_project_node(),
      estimate_normals_node(),
      support_plane_node(),
      detect_primitives_node(),
      match_models_node(),
      odometry_node(),
      track_objects_node(),
      report_node(),
      // diagnostics: engine tests and benchmarks
      identity_node(),
      checksum_node(),
      fail_on_frame_node(),
  };
}

}  // namespace mereo::nodes
