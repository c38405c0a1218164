// mereo/nodes/builtin.hpp: the library's port types and node kinds, registered into the engine.
//
// The engine (mereo/graph) knows no kinds of its own. Call register_builtin() once before
// building, loading or running a graph in C++ (the Python module and mereo-run call it):
//
//   mereo::nodes::register_builtin();
//   auto g = mereo::graph::Graph::load("graphs/tabletop.yaml");
#pragma once

namespace mereo::nodes {

/// Registers the port types (Frame, Cloud, NormalMap, Depth, Color, Labels, Mask,
/// SupportPlane, Lattice, ModelSet, Interpretation, Tracks, Segments) and the node kinds of cpp/src/nodes/ from their
/// explicit lists. Idempotent and thread-safe.
void register_builtin();

}  // namespace mereo::nodes
