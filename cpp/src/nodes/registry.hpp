// The explicit lists of the library's node kinds and port types, registered into the engine
// by mereo::nodes::register_builtin() (no static registration: see STYLE.md).
#pragma once

#include <vector>

#include "mereo/graph/node.hpp"

namespace mereo::nodes {

// One function per node file in cpp/src/nodes/; add yours here and in registry.cpp.
graph::NodeSpec frame_source_node();
graph::NodeSpec back_project_node();
graph::NodeSpec filter_depth_node();
graph::NodeSpec estimate_normals_node();
graph::NodeSpec support_plane_node();
graph::NodeSpec detect_primitives_node();
graph::NodeSpec detect_edges_node();
graph::NodeSpec find_regions_node();
graph::NodeSpec detect_patches_node();
graph::NodeSpec detect_legs_node();
graph::NodeSpec models_node();
graph::NodeSpec match_models_node();
graph::NodeSpec interpret_node();
graph::NodeSpec report_node();
graph::NodeSpec track_objects_node();
graph::NodeSpec odometry_node();

/// Every built-in kind, in the order of the list in registry.cpp.
std::vector<graph::NodeSpec> builtin_node_specs();
/// The port types that cross the library's edges (port_types.cpp; a new type goes there).
void register_port_types();

}  // namespace mereo::nodes
