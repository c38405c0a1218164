// Scoring of tracked objects over rendered sequences, shared by bench_tracking and the
// cognitive-layer tests: the tracks of each frame (graphs/tabletop_tracking.yaml's
// tracks.tracks) against the renderer's ground truth in the world frame.
//  - a track is true when its body lies within 3 cm (across the axis) of a true body of its
//    model, else false; each stretch of frames in which a false mug track is reported
//    (probability 0.5 or more) is one false mug hypothesis, dropped at the first frame it is no
//    longer reported (a rejected track reported again later is another one); for context, the
//    frames in which the view alone took a false body for a mug (a mug track of it, reported or
//    not, supported by that frame's accepted mug) are counted too, and how many of them the
//    tracker reported;
//  - a true mug is lost when, after it has been reported, a frame that shows it (body >= 500
//    pixels, handle >= 150) reports no mug track on it;
//  - id switches: per true mug, the number of times the reporting track's id changes;
//  - radius errors: of the body as each frame's own view measured it (one view), and of the
//    track's filtered body in the frames after its tenth view (fused).
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "mereo/cognitive/tracking.hpp"
#include "mereo/synthetic/scene.hpp"

namespace mereo::bench {

struct TrackingScore {
  int frames = 0;
  int false_mugs = 0, false_mugs_dropped_in_5 = 0;
  int false_mug_views = 0, false_mug_views_reported = 0;  ///< frames x false bodies a single view took for a mug
  int true_mugs = 0, true_mugs_lost = 0;
  int id_switches = 0;
  int mug_frames = 0;  ///< frames x true mugs shown
  std::vector<double> single_view_radius_mm, fused_radius_mm;
  std::vector<std::string> notes;
};

/// The true mug (object id) whose body axis passes within 3 cm of the segment's centre, world
/// frame; 0 if none.
inline std::uint32_t true_object(const Segment& body_world, const synthetic::GroundTruth& gt, const std::string& model) {
  for (const auto& o : gt.objects_truth) {
    if (o.model != model) continue;
    const auto* b = o.part("body");
    if (!b) continue;
    const Eigen::Vector3d a = b->world.axis.normalized(), q = body_world.origin() - b->world.point;
    if ((q - a * a.dot(q)).norm() <= 0.03) return o.id;
  }
  return 0;
}

/// Scores one sequence: `tracks[k]` are the live tracks after frame k (world frame: the
/// renderer's, i.e. the truth's, unless `world_from_track` maps the tracker's world into it).
inline void score_sequence(const std::vector<synthetic::SyntheticFrame>& seq,
                           const std::vector<std::vector<cognitive::Track>>& tracks, const std::string& tag,
                           TrackingScore& acc, const std::vector<Pose>& world_from_track = {}) {
  std::map<int, int> false_since;                  // false mug track id -> first frame of this report
  std::map<std::uint32_t, int> last_id;            // true mug -> id of the track reporting it
  std::map<std::uint32_t, int> views;              // true mug -> frames reported so far
  std::set<std::uint32_t> reported_once, lost, mugs;
  for (std::size_t k = 0; k < seq.size() && k < tracks.size(); ++k) {
    ++acc.frames;
    const auto& gt = seq[k].truth;
    const Pose W = world_from_track.empty() ? Pose::Identity() : world_from_track[k];
    std::map<std::uint32_t, const cognitive::Track*> reporting;
    std::set<int> reported_false;
    for (const auto& t : tracks[k]) {
      if (t.model != "mug") continue;
      const Segment body = cognitive::transformed(t.parts.front().world, W);
      const std::uint32_t id = true_object(body, gt, "mug");
      const bool reported = t.probability() >= 0.5;
      if (id == 0 && t.parts.front().segment >= 0) {  // this frame's view took it for a mug
        ++acc.false_mug_views;
        acc.false_mug_views_reported += reported;
      }
      if (!reported) continue;
      if (id == 0) {
        reported_false.insert(t.id);
        if (!false_since.count(t.id)) false_since[t.id] = int(k), ++acc.false_mugs;
      } else if (!reporting.count(id) || reporting[id]->age < t.age) {
        reporting[id] = &t;
      }
    }
    // false mug tracks no longer reported: dropped
    for (auto it = false_since.begin(); it != false_since.end();) {
      const auto [id, since] = *it;
      if (reported_false.count(id)) {
        ++it;
        continue;
      }
      acc.false_mugs_dropped_in_5 += int(k) - since <= 5;
      if (int(k) - since > 5)
        acc.notes.push_back(tag + ": false mug track " + std::to_string(id) + " reported from frame " +
                            std::to_string(since) + " to " + std::to_string(k - 1));
      it = false_since.erase(it);
    }
    for (const auto& o : gt.objects_truth) {
      if (o.model != "mug") continue;
      const auto* b = o.part("body");
      const auto* h = o.part("handle");
      const bool shown = b && h && b->visible_pixels >= 500 && h->visible_pixels >= 150;
      if (shown) mugs.insert(o.id), ++acc.mug_frames;
      const auto it = reporting.find(o.id);
      if (it == reporting.end()) {
        if (shown && reported_once.count(o.id) && !lost.count(o.id)) {
          lost.insert(o.id);
          acc.notes.push_back(tag + ": mug " + std::to_string(o.id) + " lost at frame " + std::to_string(k));
        }
        continue;
      }
      reported_once.insert(o.id);
      const int n = ++views[o.id];
      const auto& body_part = it->second->parts.front();
      if (body_part.segment >= 0)  // seen in this frame: its own measurement
        acc.single_view_radius_mm.push_back(1000 * std::abs(body_part.observed.size() - b->world.radius));
      if (n >= 10) acc.fused_radius_mm.push_back(1000 * std::abs(body_part.world.size() - b->world.radius));
      if (last_id.count(o.id) && last_id[o.id] != it->second->id) ++acc.id_switches;
      last_id[o.id] = it->second->id;
    }
  }
  for (const auto& [id, since] : false_since)
    acc.notes.push_back(tag + ": false mug track " + std::to_string(id) + " reported from frame " +
                        std::to_string(since) + " to the end");
  acc.true_mugs += int(mugs.size());
  acc.true_mugs_lost += int(lost.size());
}

}  // namespace mereo::bench
