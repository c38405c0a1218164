// interpret: the judgement step (matching::interpret): the lattice of hypotheses to the objects
// the frame is taken to hold, accepted ones first, then the alternatives they exclude; read by
// the report and the tracker.
//
//   nodes:
//     - {name: interpretation, kind: interpret, options: {min_score: 0.5}}
//   edges:
//     - objects.lattice -> interpretation.lattice
//     - models.models -> interpretation.models
//     - interpretation.objects -> result.objects
//     - primitives.segments -> interpretation.segments   # optional, the three together: every
//     - cloud.cloud -> interpretation.cloud              #   accepted object must explain its
//     - table.plane -> interpretation.plane              #   region; the rest is "unknown"
//     - normals.normals -> interpretation.normals        # optional: unknown objects that touch
//                                                        #   are apart at their silhouettes
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/explain.hpp"
#include "mereo/matching/interpret.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec interpret_node() {
  graph::NodeSpec s;
  s.kind = "interpret";
  s.doc = "The frame's interpretation: hypotheses accepted one per set of segments (most explaining first), "
          "then the alternatives they exclude.";
  s.inputs = {{"lattice", "Lattice", "the hypotheses of match_models"},
              {"models", "ModelSet", "the models they were matched from (the models node)"},
              {"segments", "Segments", "the segments (with cloud and plane: each object must explain its region)", false},
              {"cloud", "Cloud", "the frame's points", false},
              {"plane", "SupportPlane", "the support plane and its region of interest", false},
              {"normals", "NormalMap", "per-pixel normals: silhouettes separate unknown objects that touch", false}};
  s.outputs = {{"objects", "Interpretation", "the accepted objects, then the listed alternatives"}};
  s.options = options_of<matching::InterpretOptions>();
  s.make = [](const graph::Options& o) {
    const auto io = options_from<matching::InterpretOptions>(o);
    return graph::NodeBody([io](graph::NodeContext& ctx) {
      auto objects = matching::interpret(ctx.input<knowledge::ModelSet>("models").kb,
                                         ctx.input<matching::Lattice>("lattice"), io);
      if (ctx.has_input("segments") && ctx.has_input("cloud") && ctx.has_input("plane"))
        matching::explain_regions(objects, ctx.input<std::vector<Segment>>("segments"), ctx.input<Cloud>("cloud"),
                                  ctx.input<extension::SupportPlane>("plane"), io,
                                  ctx.has_input("normals") ? &ctx.input<NormalMap>("normals") : nullptr);
      ctx.output("objects", std::move(objects));
    });
  };
  return s;
}

}  // namespace mereo::nodes
