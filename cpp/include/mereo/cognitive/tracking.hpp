// mereo/cognitive/tracking.hpp: the cognitive layer: object hypotheses held across frames in the
// world frame, rescored by every new view, refined by a Kalman filter, dropped when their parts
// drift apart or the views stop supporting them.
//
// Each frame brings observations (the frame's object hypotheses, matching::interpret: accepted
// ones and their alternatives) in the camera frame and the camera's pose. For every held track:
//  - association: the observations whose body lies within `max_distance` of the track's body
//    (world frame) with a radius within `max_radius_difference`;
//  - judgement (recursive, in log-odds): an accepted observation of the track's model raises it
//    by `support * (2 score - 1)`, and each of its other parts adds `consistent` when it stays
//    where the track holds it relative to the body (within `part_tolerance`; across the body's
//    axis from the axis, along it by its own height, as the body's centre moves with its
//    visible extent) or `drifted` (negative) when it moved away from its partner (a plate's rim taken for a handle, a ring
//    leaning on a jar seen from another side); a part seen in two views in a row at the same new
//    place is re-anchored there (the first fit was off), the penalties taken stay; a body seen
//    but taken for something else adds `contradicted` (negative) in proportion to how much of
//    the parts that make the difference (those the view's accepted model lacks: a mug's handle
//    when the view says cup) the view shows where the track holds them (their area in the image,
//    in full from `visible_pixels`: a handle seen edge-on is often missed; part_visibility against
//    the frame's depth: a part hidden behind its body or another object, or where the depth is
//    missing, is no evidence; a mug seen with its handle at the back looks like a cup), and
//    `drifted` more when the view sees through where the part should be (the track's part is
//    not there: a ring fitted as a handle from another side); with depth, the points around a
//    handle (where the track holds it, off the body's wall) in the last `turn_views` views that
//    show them (at most `turn_points` of them) are fitted together, world frame, with the ring
//    plane held through the body's axis and free to turn about it: a ring that turns away
//    (HandleOptions::max_turn_deg, with a clearly better fit: turn_residual_ratio of the held
//    one) adds `drifted` per view (a ring leaning on a jar: each view alone may see it nearly
//    edge-on and pass it for a handle, the views together do not); without depth, only a part
//    behind the body and within its silhouette counts as hidden; a track not seen at all decays
//    towards undecided by `decay` per frame (belief only: the evidence against it is kept);
//  - rejected hypotheses are not forgotten: a track below `report` is not reported but is held,
//    with the evidence against it (down to `floor`), as long as its body stays in view, so that a
//    later view that happens to support it does not start it afresh; tracks unseen for
//    `max_missed` frames are dropped;
//  - a Kalman filter per track over its parts' parameters (positions, radii, height), world
//    frame, static objects: measurement noise grows with depth (z^2), a small process noise
//    absorbs pose errors.
// Accepted observations that match no track start new tracks, with stable, increasing ids, from
// `prior`: one view alone does not make a report, a second that agrees does.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/camera.hpp"
#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/features/handle.hpp"

namespace mereo::cognitive {

struct TrackOptions {
  double max_distance = 0.03;           ///< association: body centres, metres (world)
  double max_radius_difference = 0.01;  ///< association: body radii, metres
  double part_tolerance = 0.01;         ///< a part stays put relative to its body, metres
  double prior = -1.6;                  ///< log-odds of a new hypothesis before its first view: one view does not make a report
  double support = 1.5;                 ///< log-odds per supporting view, times (2 score - 1)
  double consistent = 0.5;              ///< per part that stayed put
  double drifted = -2.5;                ///< per part that moved away from its body
  double contradicted = -1.2;           ///< body seen, the model not accepted for it
  double decay = 0.9;                   ///< factor per frame unseen on a positive log-odds
  double floor = -10.0;                 ///< the log-odds held against a rejected hypothesis at most
  int max_missed = 30;                  ///< frames unseen before a track is dropped
  double report = 0.5;                  ///< probability at which a track is reported
  double measurement_noise = 0.002;     ///< sigma of a measured parameter at 1 m (grows as z^2) ...
  double reference_inliers = 1000;      ///< ... for a fit to this many pixels (falls as 1/sqrt(inliers))
  double depth_tolerance = 0.01;        ///< visibility: a surface within this of a part's is the part, metres
  double visible_pixels = 300;          ///< a part this large in the image (pixels) gives a full contradiction
  int turn_views = 8;                   ///< a handle's surroundings: the last views fitted together ...
  /// ... at most this many of their points, evenly strided (the ring and its turn have six
  /// parameters; 8 views of up to 400 points each made this fit most of the tracker's time)
  int turn_points = 200;
  /// What a handle is (its ranges; max_turn_deg: a ring the views together turn further from the
  /// body's axis is no handle): the detector's own (features/handle.hpp).
  features::HandleOptions handle;
  double process_noise = 0.0003;        ///< sigma per frame of a part's place and height (its visible extent)
  double shape_noise = 0.00002;         ///< ... of its radii: a rigid object's do not change, views average

  /// The options of the track_objects node (the rest stay at their defaults).
  static const Fields<TrackOptions>& fields();
};

inline const Fields<TrackOptions>& TrackOptions::fields() {
  using O = TrackOptions;
  static const Fields<O> head = {
      field("max_distance", &O::max_distance, 0.001, 1, "association: body centres, metres"),
      field("max_radius_difference", &O::max_radius_difference, 0.0001, 10,
            "association: body sizes (a radius; a patch's half length), metres"),
      field("part_tolerance", &O::part_tolerance, 0.001, 1, "a part stays put relative to its body"),
      field("visible_pixels", &O::visible_pixels, 1, 1e6,
            "a missing part this large in the image (pixels, where the frame's depth shows its place) is a full "
            "contradiction"),
  };
  // the handle's turn (features/handle.hpp), as the views together see it
  static const Fields<O> f = [] {
    Fields<O> out = head;
    for (auto g : nested(&O::handle, features::HandleOptions::fields()))
      if (g.name == "max_handle_turn_deg") {
        g.doc = "the last views around a handle fitted together: a ring turned further from the body's axis is no handle";
        out.push_back(std::move(g));
      }
    return concat<O>(out, {
        field("max_missed", &O::max_missed, 1, 100000, "frames unseen before a track is dropped"),
        field("report", &O::report, 0, 1, "probability at which a track is reported"),
    });
  }();
  return f;
}

/// One object hypothesis of a frame (camera frame).
struct Observation {
  std::string model;
  std::vector<std::string> is_a;  ///< the concepts the model specializes (RecognizedObject::is_a)
  double score = 0.0;
  bool accepted = false;
  std::vector<std::pair<std::string, Segment>> parts;  ///< role -> segment; "body" first if any
  std::vector<int> segments;                           ///< their indices in the frame's segments
};

/// A part's Kalman filter (static model: a prediction only adds process noise): its class's
/// tracked parameters (mereo/shapes: the centre, then sizes; world frame) and their variances.
struct PartFilter {
  Eigen::VectorXd x, P;
  std::vector<bool> size;  ///< radii, with the slow shape noise; others move with the view
  /// Starts from a measurement `m` with `variance` on each parameter.
  void reset(const Segment& m, double variance);
  /// Fuses measurement `m` with variance `r`; `along_axis` (a cylinder's unit axis): the centre's
  /// place along it follows the visible extent, so the newest view's is taken, only its place
  /// across the axis is filtered.
  void update(const Segment& m, double r, double process_noise, double shape_noise,
              const std::optional<Eigen::Vector3d>& along_axis);
};

/// A part as the track holds it: fused parameters in the world frame.
struct TrackedPart {
  std::string role;
  Segment world;
  PartFilter filter;
  int segment = -1;  ///< its segment in the last frame, -1 when not seen there
  Segment observed;  ///< as the last supporting view measured it (world frame, unfiltered)
  /// Where the last view that drifted saw it, relative to the body (world frame); a next view
  /// that agrees re-anchors the part there.
  std::optional<Eigen::Vector3d> moved_to;
  /// A handle's surroundings in the last views that showed them (world frame: the frames' depth
  /// around where the track holds it, off the body's wall), one set per view.
  std::vector<std::vector<Eigen::Vector3d>> recent_points;
};

struct Track {
  int id = 0;
  /// The concept it holds: refined to a specialization when a supporting view shows one (a
  /// chair's track becomes an office_chair's where its column is seen), never widened back.
  std::string model;
  std::vector<std::string> is_a;
  double log_odds = 0.0;
  int age = 0;        ///< frames since it started
  int hits = 0;       ///< frames with a supporting view
  int missed = 0;     ///< consecutive frames without any view of its body
  bool seen = false;  ///< its body was observed in the last frame
  double score = 0.0; ///< the last supporting observation's score
  std::vector<TrackedPart> parts;

  double probability() const;
  const TrackedPart* part(const std::string& role) const;
};

class Tracker {
 public:
  explicit Tracker(TrackOptions options = {});
  /// One frame: its observations (camera frame) and the camera-to-world pose; `depth` (the
  /// frame's, with its intrinsics), when given, tells which parts the view shows. Returns the
  /// held tracks, by id: reported ones (probability >= `report`) and rejected ones still in view.
  const std::vector<Track>& update(const std::vector<Observation>& observations, const Pose& camera_to_world,
                                   const DepthImage* depth = nullptr, const Intrinsics& intrinsics = {});
  const std::vector<Track>& tracks() const { return tracks_; }
  const TrackOptions& options() const { return options_; }
  /// Every id ever dropped (unseen for `max_missed` frames), with the frame it was dropped at
  /// (frames counted from 0).
  const std::vector<std::pair<int, int>>& dropped() const { return dropped_; }

 private:
  /// The steps of update() after each track's association, evidence and filter update: drop
  /// the tracks unseen too long; start tracks from the accepted observations no track took.
  void prune();
  void spawn(const std::vector<Observation>& world, const std::vector<bool>& used, const std::vector<double>& distance);

  TrackOptions options_;
  std::vector<Track> tracks_;
  std::vector<std::pair<int, int>> dropped_;
  int next_id_ = 0;
  int frame_ = -1;
};

/// What a view's depth shows where a part is held to be: points sampled on the part (a torus:
/// its ring, except where it runs inside `body` or so close to its wall, within `tolerance`,
/// that the wall would pass for it; others: the centre), each classed by the depth around its
/// pixel against the part's surface there.
struct Visibility {
  int there = 0;     ///< a surface at the part's depth (within `tolerance`)
  int through = 0;   ///< only surfaces well behind it: the view sees through where the part should be
  int occluded = 0;  ///< something in front of it
  int unknown = 0;   ///< no depth there, or outside the image
  double pixels = 0; ///< the part's area in the image where it is seen (there or through), pixels
  int seen() const { return there + through; }
  int total() const { return there + through + occluded + unknown; }
  Visibility& operator+=(const Visibility& o);
};
/// `part` and `body` in the camera frame.
Visibility part_visibility(const Segment& part, const Segment& body, const DepthImage& depth,
                           const Intrinsics& intrinsics, double tolerance = 0.01);

/// The depth's points (camera frame, as `part` and `body`) around a part: within its reach (a
/// torus: ring and tube radius; others: radius) plus `margin` of its centre, and more than
/// `margin` off the body's wall; at most `max_points`, evenly strided.
std::vector<Eigen::Vector3d> points_around(const Segment& part, const Segment& body, const DepthImage& depth,
                                           const Intrinsics& intrinsics, double margin = 0.005,
                                           std::size_t max_points = 400);

/// A segment moved by a pose (points transformed, axes rotated): Segment::transformed.
inline Segment transformed(const Segment& s, const Pose& T) { return s.transformed(T); }

/// The tracks at or above `report` probability as a JSON array of objects in the camera frame
/// of `camera_to_world` (DESIGN.md's "objects", with "track" = the track's id, "probability",
/// "in_view", and each part's fused parameters; "segment" is its segment in this frame, -1 when
/// it was not seen).
std::string objects_json(const std::vector<Track>& tracks, const Pose& camera_to_world, double report);

}  // namespace mereo::cognitive
