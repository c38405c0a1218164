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
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec support_plane_node() {
  using graph::OptionType;
  const extension::SupportPlaneOptions def;
  graph::NodeSpec s;
  s.kind = "support_plane";
  s.doc = "The dominant horizontal plane under the objects (the table) and the mask of the points above it.";
  s.inputs = {{"cloud", "Cloud", "organized XYZ cloud"},
              {"normals", "NormalMap", "per-pixel normals"},
              {"frame", "Frame", "the frame; when it has a pose, gravity comes from it", false}};
  s.outputs = {{"plane", "SupportPlane", "normal, offset, polygon, inliers, world frame"},
               {"roi", "Mask", "pixels above the plane, inside its polygon"}};
  s.options = {
      {"seed", OptionType::Int, 0LL, 0, 1e15, {}, "random seed of the plane hypotheses"},
      {"epsilon", OptionType::Double, def.epsilon, 1e-4, 0.1, {}, "inlier distance at 1 m, metres"},
      {"min_inliers", OptionType::Int, (long long)def.min_inliers, 10, 1e7, {}, "fewest points of the plane"},
      {"min_height", OptionType::Double, def.min_height, 0, 1, {}, "ROI: lowest height above the plane, metres"},
      {"max_height", OptionType::Double, def.max_height, 0.01, 5, {}, "ROI: highest height above the plane, metres"},
      {"margin", OptionType::Double, def.margin, -1, 1, {}, "ROI: polygon shrunk by this, metres"},
  };
  s.make = [](const graph::Options& o) {
    extension::SupportPlaneOptions p;
    p.seed = std::uint64_t(o.get_int("seed"));
    p.epsilon = o.get_double("epsilon");
    p.min_inliers = int(o.get_int("min_inliers"));
    p.min_height = o.get_double("min_height");
    p.max_height = o.get_double("max_height");
    p.margin = o.get_double("margin");
    return graph::NodeBody([p](graph::NodeContext& ctx) {
      extension::SupportPlaneOptions q = p;
      if (ctx.has_input("frame")) {
        const Frame& f = ctx.input<Frame>("frame");
        if (f.pose) q.up = f.pose->linear().transpose() * Eigen::Vector3d::UnitZ();
      }
      auto plane = extension::find_support_plane(ctx.input<Cloud>("cloud"), ctx.input<NormalMap>("normals"), q);
      ctx.output("roi", plane.roi);
      ctx.output("plane", std::move(plane));
    });
  };
  return s;
}

}  // namespace mereo::nodes
