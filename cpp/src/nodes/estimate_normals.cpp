// estimate_normals: per-pixel unit normals of an organized cloud (extension::estimate_normals).
//
//   nodes:
//     - {name: normals, kind: estimate_normals, options: {method: fast, window: 5}}
//   edges:
//     - cloud.cloud -> normals.cloud
#include "mereo/core/error.hpp"
#include "mereo/extension/normals.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec estimate_normals_node() {
  graph::NodeSpec s;
  s.kind = "estimate_normals";
  s.doc = "Per-pixel unit normals (camera frame, towards the camera, NaN where undefined); windows never cross a depth jump.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"}};
  s.outputs = {{"normals", "NormalMap", "H x W x 3 unit normals"}};
  s.options = options_of<extension::NormalOptions>();
  s.make = [](const graph::Options& o) {
    const auto n = options_from<extension::NormalOptions>(o);
    if (n.window % 2 == 0) throw InputError("option 'window' must be odd, got " + std::to_string(n.window));
    return graph::NodeBody([n](graph::NodeContext& ctx) {
      ctx.output("normals", extension::estimate_normals(ctx.input<Cloud>("cloud"), n));
    });
  };
  return s;
}

}  // namespace mereo::nodes
