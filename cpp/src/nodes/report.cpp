// report: the frame's result as one JSON line, the output of `mereo recognize` (DESIGN.md's
// contract; the runner adds "timing_ms"): its interpretation (the interpret node), or with
// tracks the tracked objects, its segments and support plane, and with a support plane the
// scene relations between the objects reported (cognitive/relations.hpp).
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
#include "mereo/cognitive/relations.hpp"
#include "mereo/cognitive/tracking.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/extension/support_plane.hpp"
#include "matching/json.hpp"
#include "nodes/node_options.hpp"
#include "nodes/options.hpp"
#include "nodes/registry.hpp"

namespace mereo::nodes {

namespace {

/// The accepted objects of a frame, and the unknown ones (regions no model explains: things
/// that stand there all the same), as the scene relations see them (ids as in the result).
std::vector<cognitive::PlacedObject> placed_objects(const std::vector<matching::RecognizedObject>& objects,
                                                    const std::vector<Segment>& segments) {
  std::vector<cognitive::PlacedObject> out;
  for (const auto& ob : objects) {
    if (!ob.accepted && !(ob.model == "unknown" && ob.region)) continue;
    cognitive::PlacedObject p;
    p.id = ob.id;
    for (const auto& [role, index] : ob.parts)
      if (index >= 0 && std::size_t(index) < segments.size())
        p.parts.insert(role == "body" ? p.parts.begin() : p.parts.end(), segments[std::size_t(index)]);
    if (p.parts.empty() && ob.region) p.box_centre = ob.region->centroid, p.box_size = ob.region->size;
    out.push_back(std::move(p));
  }
  return out;
}

/// The reported tracks (ids as the result gives them), in the camera frame.
std::vector<cognitive::PlacedObject> placed_tracks(const std::vector<cognitive::Track>& tracks, const Pose& camera_to_world,
                                                   double report) {
  const Pose camera_from_world = camera_to_world.inverse();
  std::vector<cognitive::PlacedObject> out;
  for (const cognitive::Track* t : cognitive::detail::reported_tracks(tracks, report)) {
    cognitive::PlacedObject p;
    p.id = int(out.size());
    for (const auto& part : t->parts)
      p.parts.insert(part.role == "body" ? p.parts.begin() : p.parts.end(), cognitive::transformed(part.world, camera_from_world));
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

graph::NodeSpec report_node() {
  graph::NodeSpec s;
  s.kind = "report";
  s.doc = "The frame's JSON result: its accepted objects and their alternatives (or its tracked objects), "
          "segments and support plane, and the scene relations between the objects (what each stands on).";
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
      std::vector<cognitive::PlacedObject> placed;
      if (tracked) {
        const auto& tracks = ctx.input<std::vector<cognitive::Track>>("tracks");
        const Pose camera_to_world = frame.pose.value_or(Pose::Identity());
        result["objects"] = cognitive::detail::tracks_to_json(tracks, camera_to_world, track_probability);
        placed = placed_tracks(tracks, camera_to_world, track_probability);
      } else {
        placed = placed_objects(objects, ctx.input<std::vector<Segment>>("segments"));
      }
      if (plane) {
        matching::detail::Json relations = matching::detail::Json::array();
        for (const auto& r : cognitive::scene_relations(placed, plane->normal, plane->d)) {
          matching::detail::Json j = {{"relation", r.relation}, {"subject", r.subject}};
          if (r.object == cognitive::Relation::kSupport) j["object"] = "support_plane";
          else j["object"] = r.object;
          relations.push_back(std::move(j));
        }
        result["relations"] = std::move(relations);
      }
      ctx.output("result", result.dump());
    });
  };
  return s;
}

}  // namespace mereo::nodes
