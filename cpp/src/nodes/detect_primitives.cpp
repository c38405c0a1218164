// detect_primitives: planes, cylinders, spheres and tori of an organized cloud with normals
// (features::detect_primitives), with a targeted torus search next to every cylinder.
//
//   nodes:
//     - {name: primitives, kind: detect_primitives, options: {seed: 0, min_support: 250}}
//   edges:
//     - cloud.cloud -> primitives.cloud
//     - normals.normals -> primitives.normals
//     - table.roi -> primitives.roi          # optional: only the points above the table
//     - table.plane -> primitives.plane      # optional: upright bodies on it are also looked
//                                            # for without normals
//     - source.frame -> primitives.frame     # optional: colour for the segments' hue, and the
//                                            # camera's focal length (else fitted to the cloud)
//     - raw_cloud.cloud -> primitives.unfiltered  # optional: the unfiltered points that
//                                            # cylinders and spheres are measured on (when the
//                                            # cloud's depth is filtered)
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/primitives.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec detect_primitives_node() {
  graph::NodeSpec s;
  s.kind = "detect_primitives";
  s.doc = "RANSAC planes, cylinders, spheres and tori (Schnabel et al. 2007, on the image grid), largest first.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"normals", "NormalMap", "per-pixel normals"},
              {"roi", "Mask", "only these pixels (e.g. above the table)", false},
              {"plane", "SupportPlane", "the support: upright bodies on it are also looked for without normals", false},
              {"frame", "Frame", "the frame of the cloud: the segments' colour, its camera's focal length", false},
              {"unfiltered", "Cloud", "the cloud before depth filtering: cylinders and spheres are measured on it", false}};
  s.outputs = {{"segments", "Segments", "the primitives with parameters and inlier pixels"}};
  s.options = options_of<features::DetectOptions>();
  s.make = [](const graph::Options& o) {
    const auto d = options_from<features::DetectOptions>(o);
    return graph::NodeBody([d](graph::NodeContext& ctx) {
      features::DetectOptions q = d;
      if (ctx.has_input("roi")) q.roi = ctx.input<extension::Mask>("roi");
      if (ctx.has_input("plane")) {
        const auto& plane = ctx.input<extension::SupportPlane>("plane");
        q.support << plane.normal, plane.d;
      }
      const ColorImage* color = nullptr;
      if (ctx.has_input("frame")) {
        const Frame& frame = ctx.input<Frame>("frame");
        color = &frame.color;
        q.focal_px = frame.intrinsics.fx;  // the camera's, not one fitted to the cloud
      }
      if (ctx.has_input("unfiltered")) q.unfiltered = ctx.input<Cloud>("unfiltered");
      ctx.output("segments", features::detect_primitives(ctx.input<Cloud>("cloud"), ctx.input<NormalMap>("normals"), q, color));
    });
  };
  return s;
}

}  // namespace mereo::nodes
