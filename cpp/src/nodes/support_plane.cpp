// support_plane: the table plane, its polygon, the region of interest above it and a world
// frame with z up (extension::find_support_plane).
//
//   nodes:
//     - {name: table, kind: support_plane, options: {max_height: 0.4}}
//   edges:
//     - cloud.cloud -> table.cloud
//     - normals.normals -> table.normals
//     - source.frame -> table.frame      # optional: its pose gives the direction of gravity
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec support_plane_node() {
  graph::NodeSpec s;
  s.kind = "support_plane";
  s.doc = "The dominant horizontal plane under the objects (the table) and the mask of the points above it.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"normals", "NormalMap", "per-pixel normals"},
              {"frame", "Frame", "the frame; when it has a pose, gravity comes from it", false}};
  s.outputs = {{"plane", "SupportPlane", "normal, offset, polygon, inliers, world frame"},
               {"roi", "Mask", "pixels above the plane, inside its polygon"}};
  s.options = options_of<extension::SupportPlaneOptions>();
  s.make = [](const graph::Options& o) {
    const auto p = options_from<extension::SupportPlaneOptions>(o);
    return graph::NodeBody([p](graph::NodeContext& ctx) {
      extension::SupportPlaneOptions q = p;
      if (ctx.has_input("frame")) {
        const Frame& f = ctx.input<Frame>("frame");
        if (f.pose && f.gravity_aligned) q.up = f.pose->linear().transpose() * Eigen::Vector3d::UnitZ();
      }
      auto plane = extension::find_support_plane(ctx.input<Cloud>("cloud"), ctx.input<NormalMap>("normals"), q);
      ctx.output("roi", plane.roi);
      ctx.output("plane", std::move(plane));
    });
  };
  return s;
}

}  // namespace mereo::nodes
