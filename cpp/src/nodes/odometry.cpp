// odometry: camera poses estimated frame to frame (cognitive::Odometry, OpenCV's RGB-D
// odometry) for inputs without poses, corrected against the table and the upright cylinders
// on it when the frame's support plane and segments are connected; frames in order. With
// `replace`, a pose the frame already has is replaced too (to compare the estimate with the
// truth).
//
//   nodes:
//     - {name: poses, kind: odometry}
//   edges:
//     - source.frame -> poses.frame
//     - table.plane -> poses.plane                # optional: landmarks (with segments)
//     - primitives.segments -> poses.segments     # optional
//     - poses.frame -> tracks.frame
#include <memory>

#include "mereo/cognitive/odometry.hpp"
#include "mereo/extension/support_plane.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec odometry_node() {
  graph::NodeSpec s;
  s.kind = "odometry";
  s.doc = "Camera poses from the frames (OpenCV RGB-D ICP odometry, frame to frame; the first frame is the world), "
          "corrected against the table and the upright cylinders (and handles) on it when those are connected.";
  s.inputs = {{"frame", "Frame", "an RGB-D frame"},
              {"plane", "SupportPlane", "the frame's table: the landmarks' plane (with segments)", false},
              {"segments", "Segments", "the frame's segments: its upright cylinders are landmarks", false}};
  s.outputs = {{"frame", "Frame", "the same frame with its estimated pose"}};
  s.options = options_of<OdometryNodeOptions>();
  s.ordered = true;
  s.make = [](const graph::Options& o) {
    const auto opts = options_from<OdometryNodeOptions>(o);
    auto odometry = std::make_shared<cognitive::Odometry>(opts.odometry);
    const bool replace = opts.replace;
    return graph::NodeBody([odometry, replace](graph::NodeContext& ctx) {
      Frame f = ctx.input<Frame>("frame");
      std::optional<cognitive::TablePlane> table;
      static const std::vector<Segment> none;
      const auto& segments = ctx.has_input("segments") ? ctx.input<std::vector<Segment>>("segments") : none;
      if (ctx.has_input("plane")) {
        const auto& p = ctx.input<extension::SupportPlane>("plane");
        table = cognitive::TablePlane{p.normal, p.d};
      }
      const Pose p = odometry->update(f, segments, table);
      if (replace || !f.pose) f.pose = p;
      ctx.output("frame", std::move(f));
    });
  };
  return s;
}

}  // namespace mereo::nodes
