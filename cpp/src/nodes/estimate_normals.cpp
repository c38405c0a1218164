// estimate_normals: per-pixel unit normals of an organized cloud (extension::estimate_normals).
//
//   nodes:
//     - {name: normals, kind: estimate_normals, options: {method: fast, window: 5}}
//   edges:
//     - cloud.cloud -> normals.cloud
#include "mereo/core/error.hpp"
#include "mereo/extension/normals.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec estimate_normals_node() {
  using graph::OptionType;
  const extension::NormalOptions def;
  graph::NodeSpec s;
  s.kind = "estimate_normals";
  s.doc = "Per-pixel unit normals (camera frame, towards the camera, NaN where undefined); windows never cross a depth jump.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"}};
  s.outputs = {{"normals", "NormalMap", "H x W x 3 unit normals"}};
  s.options = {
      {"method", OptionType::String, std::string("fast"), 0, 0, {"fast", "covariance"},
       "fast: least-squares tangents; covariance: PCA through integral images"},
      {"window", OptionType::Int, (long long)def.window, 3, 101, {}, "window side in pixels (odd)"},
      {"depth_change_factor", OptionType::Double, def.depth_change_factor, 1e-4, 1, {},
       "a depth jump larger than this times z breaks smoothing"},
      {"noise_depth", OptionType::Double, def.noise_depth, 0.1, 100, {},
       "metres: beyond it the jump threshold grows as z^2 (sensor noise)"},
      {"adaptive_window", OptionType::Bool, def.adaptive_window, 0, 0, {},
       "covariance: the window shrinks with depth (constant metric size)"},
      {"reference_depth", OptionType::Double, def.reference_depth, 0.1, 10, {},
       "metres: depth at which the adaptive window equals `window`"},
  };
  s.make = [](const graph::Options& o) {
    extension::NormalOptions n;
    n.method = extension::normal_method(o.get_string("method"));
    n.window = int(o.get_int("window"));
    if (n.window % 2 == 0) throw InputError("option 'window' must be odd, got " + std::to_string(n.window));
    n.depth_change_factor = o.get_double("depth_change_factor");
    n.adaptive_window = o.get_bool("adaptive_window");
    n.reference_depth = o.get_double("reference_depth");
    n.noise_depth = o.get_double("noise_depth");
    return graph::NodeBody([n](graph::NodeContext& ctx) {
      ctx.output("normals", extension::estimate_normals(ctx.input<Cloud>("cloud"), n));
    });
  };
  return s;
}

}  // namespace mereo::nodes
