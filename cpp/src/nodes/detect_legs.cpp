// detect_legs: the legs under a room's level patches (features::find_legs), appended to the
// patches: the furniture models' fine level of detail (a dining chair's legs, an office chair's
// column).
//
//   nodes:
//     - {name: legs, kind: detect_legs}
//   edges:
//     - cloud.cloud -> legs.cloud
//     - floor.plane -> legs.plane
//     - patches.segments -> legs.segments
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/legs.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec detect_legs_node() {
  graph::NodeSpec s;
  s.kind = "detect_legs";
  s.doc = "Thin upright supports under the level patches (table and chair legs, an office chair's column), as cylinders.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"plane", "SupportPlane", "the floor (heights above it)"},
              {"segments", "Segments", "the patches (detect_patches)"}};
  s.outputs = {{"segments", "Segments", "the patches, then the legs (class cylinder)"}};
  s.options = options_of<features::LegOptions>();
  s.make = [](const graph::Options& o) {
    const auto lo = options_from<features::LegOptions>(o);
    return graph::NodeBody([lo](graph::NodeContext& ctx) {
      const auto& floor = ctx.input<extension::SupportPlane>("plane");
      std::vector<Segment> out = ctx.input<std::vector<Segment>>("segments");
      if (floor.inlier_count == 0) {  // no floor: nothing to stand on (the frame's warning says why)
        ctx.output("segments", std::move(out));
        return;
      }
      for (auto& leg : features::find_legs(ctx.input<Cloud>("cloud"), out, floor.normal, floor.d, lo)) {
        leg.id = int(out.size());
        out.push_back(std::move(leg));
      }
      ctx.output("segments", std::move(out));
    });
  };
  return s;
}

}  // namespace mereo::nodes
