// find_regions: what the first interpretation left unknown (free-form regions above the support,
// matching/explain.hpp), described as segments of class region (features::describe_region) and
// appended to the primitives, for a second matching by models whose shape is free-form (a
// squeeze bottle).
//
//   nodes:
//     - {name: regions, kind: find_regions, options: {min_height: 0.02}}
//   edges:
//     - cloud.cloud -> regions.cloud
//     - table.plane -> regions.plane
//     - primitives.segments -> regions.segments
//     - first_interpretation.objects -> regions.objects
//     - source.frame -> regions.frame        # optional: the regions' colour
//     - regions.segments -> objects.segments
#include "mereo/core/frame.hpp"
#include "mereo/features/regions.hpp"
#include "mereo/matching/interpret.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec find_regions_node() {
  graph::NodeSpec s;
  s.kind = "find_regions";
  s.doc = "The unknown objects of an interpretation as free-form regions, appended to the segments.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"plane", "SupportPlane", "the support plane"},
              {"segments", "Segments", "the primitives; the regions follow them"},
              {"objects", "Interpretation", "an interpretation whose unknown objects carry their regions"},
              {"frame", "Frame", "the frame of the cloud: the regions' colour", false}};
  s.outputs = {{"segments", "Segments", "the primitives, then one segment of class region per unknown object"}};
  s.options = options_of<features::RegionOptions>();
  s.make = [](const graph::Options& o) {
    const auto ro = options_from<features::RegionOptions>(o);
    return graph::NodeBody([ro](graph::NodeContext& ctx) {
      std::vector<Segment> out = ctx.input<std::vector<Segment>>("segments");
      const Cloud& cloud = ctx.input<Cloud>("cloud");
      const auto& plane = ctx.input<extension::SupportPlane>("plane");
      const ColorImage* color = ctx.has_input("frame") ? &ctx.input<Frame>("frame").color : nullptr;
      for (const auto& u : ctx.input<std::vector<matching::RecognizedObject>>("objects"))
        if (u.region && !u.accepted)
          if (auto r = features::describe_region(cloud, plane, u.region->indices, ro, color)) {
            r->id = int(out.size());
            out.push_back(std::move(*r));
          }
      ctx.output("segments", std::move(out));
    });
  };
  return s;
}

}  // namespace mereo::nodes
