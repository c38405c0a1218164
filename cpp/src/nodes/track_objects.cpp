// track_objects: the cognitive layer (cognitive::Tracker): the frame's object hypotheses
// (its interpretation: the interpret node) associated with the tracks held across frames in the
// world frame (camera poses from the frames: the renderer's, a TUM groundtruth.txt, or the
// odometry node's), rescored, Kalman-refined, dropped; frames in order. The frame's depth tells
// which parts a view shows where a track holds them, and gives the points around its handles.
//
//   nodes:
//     - {name: tracks, kind: track_objects}
//   edges:
//     - source.frame -> tracks.frame          # its pose (identity when it has none)
//     - primitives.segments -> tracks.segments
//     - interpretation.objects -> tracks.objects
//     - tracks.tracks -> result.tracks
#include <memory>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/matching/interpret.hpp"
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
              {"objects", "Interpretation", "the frame's hypotheses, accepted or not (interpret)"}};
  s.outputs = {{"tracks", "Tracks", "the live tracks, by id"}};
  s.options = options_of<cognitive::TrackOptions>();
  s.ordered = true;
  s.make = [](const graph::Options& o) {
    auto tracker = std::make_shared<cognitive::Tracker>(options_from<cognitive::TrackOptions>(o));  // one per run
    return graph::NodeBody([tracker](graph::NodeContext& ctx) {
      const auto& segments = ctx.input<std::vector<Segment>>("segments");
      const auto& frame = ctx.input<Frame>("frame");
      std::vector<cognitive::Observation> obs;
      for (const auto& r : ctx.input<std::vector<matching::RecognizedObject>>("objects")) {
        cognitive::Observation ob;
        ob.model = r.model, ob.is_a = r.is_a, ob.score = r.score, ob.accepted = r.accepted;
        for (const auto& [role, k] : r.parts) ob.parts.emplace_back(role, segments.at(std::size_t(k))), ob.segments.push_back(k);
        obs.push_back(std::move(ob));
      }
      ctx.output("tracks", tracker->update(obs, frame.pose.value_or(Pose::Identity()), &frame.depth, frame.intrinsics));
    });
  };
  return s;
}

}  // namespace mereo::nodes
