// report: the frame's result as one JSON line, the output of `mereo recognize` (DESIGN.md's
// contract; the runner adds "timing_ms"): its interpretation (the interpret node), or with
// tracks the tracked objects, its segments and support plane.
//
//   nodes:
//     - {name: result, kind: report}
//   edges:
//     - source.frame -> result.frame
//     - primitives.segments -> result.segments
//     - interpretation.objects -> result.objects
//     - table.plane -> result.plane           # optional: reported as "support_plane"
//     - tracks.tracks -> result.tracks        # optional: the tracked objects are reported
#include "cognitive/json.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "matching/json.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec report_node() {
  graph::NodeSpec s;
  s.kind = "report";
  s.doc = "The frame's JSON result: its accepted objects and their alternatives (or its tracked objects), "
          "segments and support plane.";
  s.inputs = {{"frame", "Frame", "the frame (its id and source)"},
              {"segments", "Segments", "the frame's segments"},
              {"objects", "Interpretation", "the frame's interpretation (interpret)"},
              {"plane", "SupportPlane", "the support plane, reported when given", false},
              {"tracks", "Tracks", "tracked objects (track_objects): reported instead of the frame's own", false}};
  s.outputs = {{"result", "Text", "the frame's result, one JSON object"}};
  s.options = options_of<ReportNodeOptions>();
  s.make = [](const graph::Options& o) {
    const auto opts = options_from<ReportNodeOptions>(o);
    return graph::NodeBody([track_probability = opts.track_probability](graph::NodeContext& ctx) {
      const Frame& frame = ctx.input<Frame>("frame");
      const extension::SupportPlane* plane =
          ctx.has_input("plane") ? &ctx.input<extension::SupportPlane>("plane") : nullptr;
      const bool tracked = ctx.has_input("tracks");  // the tracks are the objects, not this frame's own
      static const std::vector<matching::RecognizedObject> none;
      const auto& objects = tracked ? none : ctx.input<std::vector<matching::RecognizedObject>>("objects");
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
