// detect_patches: the bounded planar patches of a frame (features::planar_patches), the primitives
// of a room: floor, walls, table tops, seats, backs, doors.
//
//   nodes:
//     - {name: patches, kind: detect_patches, options: {step: 2}}
//   edges:
//     - cloud.cloud -> patches.cloud
//     - normals.normals -> patches.normals
//     - floor.plane -> patches.plane          # optional: gravity (upright patches' rectangles)
//     - source.frame -> patches.frame         # optional: the patches' colour
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/features/patches.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec detect_patches_node() {
  graph::NodeSpec s;
  s.kind = "detect_patches";
  s.doc = "Bounded planar patches (floor, walls, table tops, seats, doors) by organized region growing.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"normals", "NormalMap", "per-pixel normals"},
              {"plane", "SupportPlane", "the floor: its normal is up (upright patches' rectangles)", false},
              {"frame", "Frame", "the frame of the cloud: the patches' colour", false}};
  s.outputs = {{"segments", "Segments", "the patches, largest first"}};
  s.options = options_of<features::PatchOptions>();
  s.make = [](const graph::Options& o) {
    const auto po = options_from<features::PatchOptions>(o);
    return graph::NodeBody([po](graph::NodeContext& ctx) {
      std::optional<Eigen::Vector3d> up;
      if (ctx.has_input("plane")) up = ctx.input<extension::SupportPlane>("plane").normal;
      const ColorImage* color = ctx.has_input("frame") ? &ctx.input<Frame>("frame").color : nullptr;
      ctx.output("segments", features::planar_patches(ctx.input<Cloud>("cloud"), ctx.input<NormalMap>("normals"), po,
                                                      up ? &*up : nullptr, color));
    });
  };
  return s;
}

}  // namespace mereo::nodes
