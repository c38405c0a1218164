// track_objects: the cognitive layer (cognitive::Tracker): the frame's object hypotheses
// (matching::interpret of the lattice) associated with the tracks held across frames in the
// world frame (camera poses from the frames: the renderer's, a TUM groundtruth.txt, or the
// odometry node's), rescored, Kalman-refined, dropped; frames in order. The frame's depth tells
// which parts a view shows where a track holds them, and gives the points around its handles.
//
//   nodes:
//     - {name: tracks, kind: track_objects}
//   edges:
//     - source.frame -> tracks.frame          # its pose (identity when it has none)
//     - primitives.segments -> tracks.segments
//     - objects.lattice -> tracks.lattice
//     - tracks.tracks -> result.tracks
#include <memory>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/interpret.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

graph::NodeSpec track_objects_node() {
  graph::NodeSpec s;
  s.kind = "track_objects";
  s.doc = "Object hypotheses tracked across frames (world frame): rescored per view, Kalman-refined, rejected when "
          "their parts drift apart; stable track ids.";
  s.inputs = {{"frame", "Frame", "the frame; its pose (camera to world) places the hypotheses"},
              {"segments", "Segments", "the frame's segments"},
              {"lattice", "Lattice", "the frame's hypotheses (match_models)"}};
  s.outputs = {{"tracks", "Tracks", "the live tracks, by id"}};
  s.options = options_of<TrackObjectsNodeOptions>();
  s.ordered = true;
  s.make = [](const graph::Options& o) {
    const auto opts = options_from<TrackObjectsNodeOptions>(o);
    auto kb = std::make_shared<const knowledge::KnowledgeBase>(knowledge::models_from(opts.file));
    auto tracker = std::make_shared<cognitive::Tracker>(opts.track);  // one per run: the body is made per run
    return graph::NodeBody([kb, tracker](graph::NodeContext& ctx) {
      const auto& segments = ctx.input<std::vector<Segment>>("segments");
      const auto& frame = ctx.input<Frame>("frame");
      std::vector<cognitive::Observation> obs;
      for (const auto& r : matching::interpret(*kb, ctx.input<matching::Lattice>("lattice"))) {
        cognitive::Observation ob;
        ob.model = r.model, ob.score = r.score, ob.accepted = r.accepted;
        for (const auto& [role, k] : r.parts) ob.parts.emplace_back(role, segments.at(std::size_t(k))), ob.segments.push_back(k);
        obs.push_back(std::move(ob));
      }
      ctx.output("tracks", tracker->update(obs, frame.pose.value_or(Pose::Identity()), &frame.depth, frame.intrinsics));
    });
  };
  return s;
}

}  // namespace mereo::nodes
