// match_models: the object layer: the concepts of the graph's models (the models node) matched
// to the frame's segments (matching::recognize), the lattice of hypotheses with mutual-exclusion
// arcs.
//
//   nodes:
//     - {name: objects, kind: match_models, options: {best: 5}}
//   edges:
//     - primitives.segments -> objects.segments
//     - models.models -> objects.models
//     - source.frame -> objects.frame      # optional: its pose gives "up"
//     - table.plane -> objects.plane       # optional: the table's normal is "up"
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/match.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec match_models_node() {
  graph::NodeSpec s;
  s.kind = "match_models";
  s.doc = "Object hypotheses: concepts matched to the segments by branch and bound, with exclusion arcs.";
  s.inputs = {{"segments", "Segments", "the frame's segments (camera frame)"},
              {"models", "ModelSet", "the knowledge base and the concepts to look for (the models node)"},
              {"frame", "Frame", "the frame; with a pose, 'up' comes from it (else the camera's -y)", false},
              {"plane", "SupportPlane", "the support plane; its normal is 'up' (before the frame's pose)", false}};
  s.outputs = {{"lattice", "Lattice", "hypotheses (best first per concept) and exclusion arcs"}};
  s.options = options_of<MatchModelsNodeOptions>();
  s.make = [](const graph::Options& o) {
    const auto opts = options_from<MatchModelsNodeOptions>(o);
    return graph::NodeBody([mo = opts.match](graph::NodeContext& ctx) {
      matching::MatchOptions m = mo;
      if (ctx.has_input("frame")) {
        const Frame& f = ctx.input<Frame>("frame");
        if (f.pose) m.context.up = f.pose->linear().transpose() * Eigen::Vector3d::UnitZ();
      }
      if (ctx.has_input("plane")) {
        const auto& p = ctx.input<extension::SupportPlane>("plane");
        if (p.inlier_count > 0) m.context.up = p.normal, m.context.support_d = p.d;
      }
      const auto& models = ctx.input<knowledge::ModelSet>("models");
      ctx.output("lattice", matching::recognize(models.kb, models.concepts, ctx.input<std::vector<Segment>>("segments"), m));
    });
  };
  return s;
}

}  // namespace mereo::nodes
