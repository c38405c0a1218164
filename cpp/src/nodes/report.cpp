// report: the judgement step (matching::interpret) and the frame's result as one JSON line, the
// output of `mereo recognize` (DESIGN.md's contract; the runner adds "timing_ms").
//
//   nodes:
//     - {name: result, kind: report, options: {min_score: 0.5}}
//   edges:
//     - source.frame -> result.frame
//     - primitives.segments -> result.segments
//     - objects.lattice -> result.lattice
//     - table.plane -> result.plane           # optional: reported as "support_plane"
#include "cognitive/json.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "matching/json.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec report_node() {
  graph::NodeSpec s;
  s.kind = "report";
  s.doc = "The accepted objects (one per set of segments, most explaining first) and the frame's JSON result.";
  s.inputs = {{"frame", "Frame", "the frame (its id and source)"},
              {"segments", "Segments", "the frame's segments"},
              {"lattice", "Lattice", "the hypotheses of match_models"},
              {"plane", "SupportPlane", "the support plane, reported when given", false},
              {"tracks", "Tracks", "tracked objects (track_objects): reported instead of the frame's own", false}};
  s.outputs = {{"result", "Text", "the frame's result, one JSON object"}};
  s.options = options_of<ReportNodeOptions>();
  s.make = [](const graph::Options& o) {
    const auto opts = options_from<ReportNodeOptions>(o);
    auto kb = std::make_shared<const knowledge::KnowledgeBase>(knowledge::models_from(opts.file));
    return graph::NodeBody([kb, io = opts.interpret, track_probability = opts.track_probability](graph::NodeContext& ctx) {
      const Frame& frame = ctx.input<Frame>("frame");
      const extension::SupportPlane* plane =
          ctx.has_input("plane") ? &ctx.input<extension::SupportPlane>("plane") : nullptr;
      const bool tracked = ctx.has_input("tracks");  // the tracks are the objects: no judgement of this frame's own
      const auto objects =
          tracked ? std::vector<matching::RecognizedObject>{} : matching::interpret(*kb, ctx.input<matching::Lattice>("lattice"), io);
      auto result = matching::detail::result_to_json(frame, ctx.input<std::vector<Segment>>("segments"), objects, plane, {});
      if (tracked)
        result["objects"] = cognitive::detail::tracks_to_json(ctx.input<std::vector<cognitive::Track>>("tracks"),
                                                             frame.pose.value_or(Pose::Identity()), track_probability);
      ctx.output("result", result.dump());
    });
  };
  return s;
}

}  // namespace mereo::nodes
