// Tracking object hypotheses across frames (see tracking.hpp).
#include "mereo/cognitive/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "cognitive/json.hpp"
#include "features/fit.hpp"

namespace mereo::cognitive {

using shapes::across;

void PartFilter::reset(const Segment& m, double variance) {
  shapes::TrackedParams t;
  m.visit([&](const auto& s) { s.tracked(t); });
  x = Eigen::Map<const Eigen::VectorXd>(t.value.data(), Eigen::Index(t.value.size()));
  P = Eigen::VectorXd::Constant(x.size(), variance);
  size = t.size;
}

void PartFilter::update(const Segment& m, double r, double process_noise, double shape_noise,
                        const std::optional<Eigen::Vector3d>& along_axis) {
  shapes::TrackedParams z;
  m.visit([&](const auto& s) { s.tracked(z); });
  if (along_axis) {
    // the centre along the axis follows the visible extent: only its position across the axis
    // is measured; along the axis the track keeps the newest view's
    const Eigen::Vector3d& a = *along_axis;
    const Eigen::Vector3d zc(z.value[0], z.value[1], z.value[2]);
    x.head<3>() += a * a.dot(zc - x.head<3>());
  }
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double q = size[std::size_t(i)] ? shape_noise : process_noise;
    P(i) += q * q;
    const double gain = P(i) / (P(i) + r);
    x(i) += gain * (z.value[std::size_t(i)] - x(i));
    P(i) *= 1 - gain;
  }
}

namespace {

const Segment* body_of(const Observation& o) {
  for (const auto& [role, s] : o.parts)
    if (role == "body") return &s;
  return o.parts.empty() ? nullptr : &o.parts.front().second;
}

/// The variance of a part's measured parameters: `measurement_noise` at 1 m for a fit to
/// `reference_inliers` pixels, growing as z^2 and falling as 1/sqrt(inliers).
double measurement_variance(const Segment& part, double distance, const TrackOptions& o) {
  const double inliers = part.inliers > 0 ? double(part.inliers) : o.reference_inliers;
  return std::pow(o.measurement_noise * distance * distance, 2) * o.reference_inliers / inliers;
}

/// The track's body (its first part).
const Segment& track_body(const Track& t) { return t.parts.front().world; }

/// A shape whose centre is the middle of its visible extent along its axis (a cylinder): that
/// place moves with the view, so only the place across the axis identifies it.
std::optional<Eigen::Vector3d> view_axis(const Segment& s) {
  if (s.view_centred()) return Eigen::Vector3d(s.direction()->normalized());
  return std::nullopt;
}

bool same_body(const Segment& a, const Segment& b, const TrackOptions& o) {
  if (a.cls() != b.cls()) return false;
  const Eigen::Vector3d d = a.origin() - b.origin();
  const auto axis = view_axis(a);
  const double apart = axis ? across(d, *axis).norm() : d.norm();
  return apart <= o.max_distance && std::abs(a.size() - b.size()) <= o.max_radius_difference;
}

/// The index of `role` among the observation's parts, -1 if absent.
int part_index(const Observation& o, const std::string& role) {
  for (std::size_t k = 0; k < o.parts.size(); ++k)
    if (o.parts[k].first == role) return int(k);
  return -1;
}

/// The frame's segment of the observation's part k (-1 when not given).
int segment_of(const Observation& o, int k) { return k >= 0 && std::size_t(k) < o.segments.size() ? o.segments[std::size_t(k)] : -1; }

/// Where a part sits relative to its body (world frame, along the unit `axis` of the track's
/// body where it has one): its centre's offset from the body's axis across it, and its height
/// along the axis. The height is the centre's own, not relative to the body's centre: a
/// cylinder's centre is the middle of its visible extent, which moves when something hides its
/// lower or upper part. A body without an axis (a sphere): the offset from its centre.
Eigen::Vector3d offset(const Segment& part, const Segment& body, const std::optional<Eigen::Vector3d>& axis) {
  if (!axis) return part.origin() - body.origin();
  return across(part.origin() - body.origin(), *axis) + *axis * axis->dot(part.origin());
}

/// This view's points around the track's handles, fitted with those of the last views (world
/// frame): `drifted` for each handle whose ring would rather turn away from the body's axis.
double handle_evidence(Track& t, const DepthImage& depth, const Intrinsics& K, const Pose& camera_to_world,
                       const Pose& to_camera, const TrackOptions& o) {
  double delta = 0.0;
  const Segment& body = track_body(t);
  if (!body.is<shapes::Cylinder>()) return delta;
  const Segment body_camera = body.transformed(to_camera);
  for (std::size_t p = 1; p < t.parts.size(); ++p) {
    TrackedPart& part = t.parts[p];
    if (!part.world.is<shapes::Torus>()) continue;
    auto points = points_around(part.world.transformed(to_camera), body_camera, depth, K);
    if (points.size() < 30) continue;  // hidden, or out of view
    for (auto& q : points) q = camera_to_world * q;
    part.recent_points.push_back(std::move(points));
    if (int(part.recent_points.size()) > o.turn_views) part.recent_points.erase(part.recent_points.begin());
    if (part.recent_points.size() < 2) continue;
    std::vector<Eigen::Vector3d> views, buffer;
    for (const auto& v : part.recent_points) views.insert(views.end(), v.begin(), v.end());
    const auto& all = features::detail::subsample_into(views, buffer, std::size_t(std::max(6, o.turn_points)));
    // the ring with the plane held (the tube too, if letting it go makes it implausibly fat)
    const Segment held = features::refit_handle_or_hold(body, part.world, all,
                                                        [&](const Segment& s) { return o.handle.plausible(s); });
    if (features::handle_turn(body, held, all).turned_away(o.handle)) delta += o.drifted;
  }
  return delta;
}

/// One frame as the steps of Tracker::update read it.
struct View {
  std::vector<Observation> world;  ///< the observations in the world frame
  std::vector<double> distance;    ///< each one's distance from the camera (its measurement noise)
  std::vector<bool> used;          ///< taken by a track
  Pose camera_to_world, to_camera;
  const DepthImage* depth = nullptr;
  Intrinsics K;
  bool has_depth() const { return depth && !depth->empty(); }
};

/// Evidence in log-odds, bounded: at most `floor` against a hypothesis, 20 for it.
void add_evidence(Track& t, double delta, const TrackOptions& o) {
  t.log_odds = std::clamp(t.log_odds + delta, o.floor, 20.0);
}

/// `model` is among the concepts of an is_a list.
bool names(const std::vector<std::string>& is_a, const std::string& model) {
  return std::find(is_a.begin(), is_a.end(), model) != is_a.end();
}

/// The observation names the track's model, one that specializes it or one it specializes (a
/// chair's track, and an office_chair seen where its column shows). Siblings are not (a mug's
/// track, and a cup seen where its handle should show: evidence against the mug).
bool same_kind(const Track& t, const Observation& ob) {
  return ob.model == t.model || names(ob.is_a, t.model) || names(t.is_a, ob.model);
}

/// Associate: the observations of the track's body; the best accepted one of its model (or of a
/// kind of it) is the support (-1: none). Sets t.seen.
int associate(Track& t, const View& view, const TrackOptions& o) {
  int support = -1;
  bool seen = false;
  for (std::size_t k = 0; k < view.world.size(); ++k) {
    const Segment* b = body_of(view.world[k]);
    if (!b || !same_body(*b, track_body(t), o)) continue;
    seen = true;
    const Observation& ob = view.world[k];
    if (ob.accepted && same_kind(t, ob) && (support < 0 || ob.score > view.world[std::size_t(support)].score))
      support = int(k);
  }
  t.seen = seen;
  return support;
}

/// Evidence of a view that sees the body but does not take it for the track's model: a
/// contradiction, as strong as the view shows the parts that would make the difference where the
/// track holds them.
void contradiction(Track& t, const View& view, const TrackOptions& o) {
  std::vector<std::string> roles;  // the parts of the model the view took the body for
  for (const Observation& ob : view.world)
    if (ob.accepted && body_of(ob) && same_body(*body_of(ob), track_body(t), o))
      for (const auto& [role, s] : ob.parts) roles.push_back(role);
  Visibility v;
  if (view.has_depth()) {
    const Segment body = track_body(t).transformed(view.to_camera);
    for (std::size_t p = 1; p < t.parts.size(); ++p)
      if (!t.parts[p].world.inward && std::find(roles.begin(), roles.end(), t.parts[p].role) == roles.end())
        v += part_visibility(t.parts[p].world.transformed(view.to_camera), body, *view.depth, view.K, o.depth_tolerance);
  }
  if (v.total() > 0) {
    const double shown = std::min(1.0, v.pixels / o.visible_pixels);
    if (shown > 0) add_evidence(t, o.contradicted * shown + (2 * v.through > v.seen() ? o.drifted * shown : 0.0), o);
    return;
  }
  // without depth: a part behind the body and within its silhouette is hidden (a mug seen
  // with its handle at the back looks like a cup)
  const Eigen::Vector3d body = view.to_camera * track_body(t).origin(), ray = body.normalized();
  bool hidden = false;
  for (std::size_t p = 1; p < t.parts.size(); ++p) {
    const Eigen::Vector3d rel = view.to_camera * t.parts[p].world.origin() - body;
    const double along = rel.dot(ray), lateral = (rel - ray * along).norm();
    hidden = hidden || (along > 0 && lateral < track_body(t).size());
  }
  if (!hidden) add_evidence(t, o.contradicted, o);
}

/// Evidence and update of a track from its supporting observation: each part consistent with
/// the body where the track holds it (fused by its filter), drifted away (evidence against), or
/// re-anchored where two views in a row agree on a new place.
void update_parts(Track& t, const Observation& ob, double distance, const TrackOptions& o) {
  ++t.hits;
  // a view that shows what the track's kind is (a chair's legs: a dining chair) refines it, and a
  // view that does not (its back alone) keeps it
  if (names(ob.is_a, t.model)) t.model = ob.model, t.is_a = ob.is_a;
  t.score = ob.score;
  double delta = o.support * (2 * ob.score - 1);
  const Segment& body_now = *body_of(ob);
  std::vector<const Segment*> fuse(t.parts.size(), nullptr);
  std::vector<bool> reanchor(t.parts.size(), false);
  for (std::size_t p = 0; p < t.parts.size(); ++p) {
    const int k = part_index(ob, t.parts[p].role);
    if (k < 0) continue;
    const Segment& seen_part = ob.parts[std::size_t(k)].second;
    t.parts[p].segment = segment_of(ob, k);
    t.parts[p].observed = seen_part;
    if (p == 0) {
      fuse[p] = &seen_part;
      continue;
    }
    TrackedPart& held = t.parts[p];
    const auto dir = track_body(t).direction();
    const std::optional<Eigen::Vector3d> axis = dir ? std::optional<Eigen::Vector3d>(dir->normalized()) : std::nullopt;
    const Eigen::Vector3d now = offset(seen_part, body_now, axis);
    if ((now - offset(held.world, track_body(t), axis)).norm() <= o.part_tolerance) {
      delta += o.consistent;
      fuse[p] = &seen_part;
      held.moved_to.reset();
    } else if (held.moved_to && (now - *held.moved_to).norm() <= o.part_tolerance) {
      // two views in a row agree on a new place: the part was first fitted off; re-anchor it
      // there (its filter restarts from this view), the penalties already taken stay
      held.world = seen_part;
      held.moved_to.reset();
      held.recent_points.clear();
      reanchor[p] = true;
    } else {
      delta += o.drifted;
      held.moved_to = now;
    }
  }
  add_evidence(t, delta, o);
  // the filters of the parts that hold
  for (std::size_t p = 0; p < t.parts.size(); ++p) {
    TrackedPart& part = t.parts[p];
    if (reanchor[p]) part.filter.reset(part.world, measurement_variance(part.world, distance, o));
    if (!fuse[p]) continue;
    const Segment& m = *fuse[p];
    Segment& w = part.world;
    part.filter.update(m, measurement_variance(m, distance, o), o.process_noise, o.shape_noise, view_axis(w));
    // axes: a running mean, sign-aligned
    if (const auto seen_axis = m.direction()) {
      Eigen::Vector3d axis = seen_axis->normalized();
      const Eigen::Vector3d held_axis = *w.direction();
      if (axis.dot(held_axis) < 0) axis = -axis;
      const Eigen::Vector3d mean = (held_axis.normalized() * double(t.hits - 1) + axis).normalized();
      w.visit([&](auto& s) { s.set_direction(mean); });
    }
    w.visit([&](auto& s) { s.set_tracked(part.filter.x.data()); });
    w.inliers = m.inliers;
  }
}

}  // namespace

std::vector<Eigen::Vector3d> points_around(const Segment& part, const Segment& body, const DepthImage& depth,
                                           const Intrinsics& K, double margin, std::size_t max_points) {
  std::vector<Eigen::Vector3d> out;
  const Eigen::Vector3d c = part.origin();
  if (depth.empty() || c.z() < 0.1) return out;
  // a ring: its whole extent; others: their size (radius)
  const double reach = (part.is<shapes::Torus>() ? part.extent() : part.size()) + margin;
  const auto* wall = body.get_if<shapes::Cylinder>();
  const Eigen::Vector2i c_px = K.pixel(c);
  const int u0 = c_px.x(), v0 = c_px.y();
  const int w = int(std::ceil(K.fx * reach / std::max(0.1, c.z() - reach)));
  for (int v = std::max(0, v0 - w); v <= std::min(depth.rows() - 1, v0 + w); ++v)
    for (int u = std::max(0, u0 - w); u <= std::min(depth.cols() - 1, u0 + w); ++u) {
      const double z = depth(v, u);
      if (!std::isfinite(z) || z <= 0) continue;
      const Eigen::Vector3d p = K.point(u, v, z);
      if ((p - c).norm() > reach) continue;
      if (wall && across(p - wall->point, wall->axis.normalized()).norm() < wall->radius + margin) continue;
      out.push_back(p);
    }
  if (out.size() > max_points) {
    std::vector<Eigen::Vector3d> kept;
    features::detail::subsample_into(out, kept, max_points);
    out = std::move(kept);
  }
  return out;
}

Visibility& Visibility::operator+=(const Visibility& o) {
  there += o.there, through += o.through, occluded += o.occluded, unknown += o.unknown, pixels += o.pixels;
  return *this;
}

Visibility part_visibility(const Segment& part, const Segment& body, const DepthImage& depth, const Intrinsics& K,
                           double tolerance) {
  // the points to look at, what each stands for (metres^2 facing the camera), and the part's
  // thickness about them
  std::vector<Eigen::Vector3d> points;
  double thickness = 0.0, area = 0.0;
  if (const auto* ring = part.get_if<shapes::Torus>()) {
    constexpr int kSamples = 36;
    const Eigen::Vector3d n = ring->normal.normalized();
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const auto* wall = body.get_if<shapes::Cylinder>();
    for (int k = 0; k < kSamples; ++k) {
      const double phi = 2 * M_PI * k / kSamples;
      const Eigen::Vector3d p = ring->center + ring->major_radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
      // inside the body, or so close to its wall that the wall would pass for the part
      if (wall && across(p - wall->point, wall->axis.normalized()).norm() < wall->radius + ring->minor_radius + tolerance)
        continue;
      points.push_back(p);
    }
    thickness = ring->minor_radius;
    area = 2 * M_PI * ring->major_radius / kSamples * 2 * ring->minor_radius;
  } else {
    points.push_back(part.origin());
    thickness = part.solid() ? part.size() : 0.0;
    area = M_PI * part.size() * part.size();
  }
  Visibility v;
  for (const Eigen::Vector3d& p : points) {
    if (p.z() < 0.1) {
      ++v.unknown;
      continue;
    }
    const Eigen::Vector2i px = K.pixel(p);
    const int u = px.x(), r = px.y();
    const int w = std::clamp(int(std::ceil(K.fx * (thickness + 0.004) / p.z())), 1, 8);
    int near = 0, front = 0, behind = 0;
    for (int y = std::max(0, r - w); y <= std::min(depth.rows() - 1, r + w); ++y)
      for (int x = std::max(0, u - w); x <= std::min(depth.cols() - 1, u + w); ++x) {
        const float z = depth(y, x);
        if (!std::isfinite(z) || z <= 0) continue;
        if (z < p.z() - thickness - tolerance) ++front;
        else if (z > p.z() + thickness + tolerance) ++behind;
        else ++near;
      }
    if (near) ++v.there;
    else if (front + behind == 0) ++v.unknown;
    else if (front >= behind) ++v.occluded;
    else ++v.through;
    if (near || behind > front) v.pixels += area * K.fx * K.fy / (p.z() * p.z());
  }
  return v;
}

double Track::probability() const { return 1.0 / (1.0 + std::exp(-log_odds)); }

const TrackedPart* Track::part(const std::string& role) const {
  for (const auto& p : parts)
    if (p.role == role) return &p;
  return nullptr;
}

Tracker::Tracker(TrackOptions options) : options_(options) {}

const std::vector<Track>& Tracker::update(const std::vector<Observation>& observations, const Pose& camera_to_world,
                                          const DepthImage* depth, const Intrinsics& intrinsics) {
  ++frame_;
  const TrackOptions& o = options_;
  View view;
  view.world = observations;
  view.distance.assign(observations.size(), 1.0);
  view.used.assign(observations.size(), false);
  view.camera_to_world = camera_to_world, view.to_camera = camera_to_world.inverse();
  view.depth = depth, view.K = intrinsics;
  for (std::size_t k = 0; k < view.world.size(); ++k) {
    for (auto& [role, s] : view.world[k].parts) s = s.transformed(camera_to_world);
    if (const Segment* b = body_of(observations[k])) view.distance[k] = std::max(0.3, b->origin().z());
  }
  // a handle's surroundings, whether or not this view found its body: each track's on its own
  // thread (it reads and keeps only that track's parts, which the loop below changes only after)
  std::vector<double> ring(tracks_.size(), 0.0);
  if (view.has_depth())
    tbb::parallel_for(std::size_t(0), tracks_.size(), [&](std::size_t k) {
      ring[k] = handle_evidence(tracks_[k], *depth, intrinsics, camera_to_world, view.to_camera, o);
    });
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    Track& t = tracks_[k];
    ++t.age;
    for (auto& p : t.parts) p.segment = -1;
    const int support = associate(t, view, o);
    if (ring[k] != 0) add_evidence(t, ring[k], o);
    if (!t.seen) {
      if (t.log_odds > 0) t.log_odds *= o.decay;
      ++t.missed;
      continue;
    }
    t.missed = 0;
    if (support < 0) {
      contradiction(t, view, o);
      continue;
    }
    view.used[std::size_t(support)] = true;
    update_parts(t, view.world[std::size_t(support)], view.distance[std::size_t(support)], o);
  }
  prune();
  spawn(view.world, view.used, view.distance);
  std::sort(tracks_.begin(), tracks_.end(), [](const Track& a, const Track& b) { return a.id < b.id; });
  return tracks_;
}

void Tracker::prune() {
  // drop what has been out of view too long (rejected hypotheses in view are held)
  std::vector<Track> kept;
  for (Track& t : tracks_) {
    if (t.missed > options_.max_missed) {
      dropped_.push_back({t.id, frame_});
      continue;
    }
    kept.push_back(std::move(t));
  }
  tracks_ = std::move(kept);
}

void Tracker::spawn(const std::vector<Observation>& world, const std::vector<bool>& used,
                    const std::vector<double>& distance) {
  // new tracks from the accepted observations that no track took
  const TrackOptions& o = options_;
  for (std::size_t k = 0; k < world.size(); ++k) {
    const Observation& ob = world[k];
    if (used[k] || !ob.accepted || !body_of(ob)) continue;
    bool taken = false;  // another track of the same model (or kind) already holds this body
    for (const Track& t : tracks_) taken = taken || (same_kind(t, ob) && same_body(*body_of(ob), track_body(t), o));
    if (taken) continue;
    Track t;
    t.id = next_id_++;
    t.model = ob.model, t.is_a = ob.is_a;
    t.log_odds = o.prior + o.support * (2 * ob.score - 1);
    t.hits = 1, t.seen = true, t.score = ob.score;
    // the body first, then the other parts
    std::vector<int> order(ob.parts.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::stable_partition(order.begin(), order.end(), [&](int i) { return ob.parts[std::size_t(i)].first == "body"; });
    for (std::size_t p = 0; p < order.size(); ++p) {
      const auto& [role, part] = ob.parts[std::size_t(order[p])];
      TrackedPart tp{role, part, {}, segment_of(ob, order[p]), part, std::nullopt, {}};
      tp.filter.reset(part, measurement_variance(part, distance[k], o));
      t.parts.push_back(std::move(tp));
    }
    tracks_.push_back(std::move(t));
  }
}

namespace detail {

std::vector<const Track*> reported_tracks(const std::vector<Track>& tracks, double report) {
  std::vector<const Track*> out;
  for (const Track& t : tracks)
    if (!(t.probability() < report)) out.push_back(&t);
  return out;
}

matching::detail::Json tracks_to_json(const std::vector<Track>& tracks, const Pose& camera_to_world, double report) {
  using matching::detail::Json;
  const Pose camera_from_world = camera_to_world.inverse();
  Json out = Json::array();
  for (const Track* track : reported_tracks(tracks, report)) {
    const Track& t = *track;
    Json o;
    o["id"] = out.size(), o["model"] = t.model, o["is_a"] = t.is_a, o["score"] = t.score, o["probability"] = t.probability();
    o["accepted"] = true, o["track"] = t.id, o["in_view"] = t.seen, o["age"] = t.age;
    o["parts"] = Json::object();
    for (const auto& p : t.parts) {
      Json part;
      part["segment"] = p.segment;
      part.update(matching::detail::segment_to_json(transformed(p.world, camera_from_world)));
      o["parts"][p.role] = std::move(part);
    }
    o["excludes"] = Json::array();
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace detail

std::string objects_json(const std::vector<Track>& tracks, const Pose& camera_to_world, double report) {
  return detail::tracks_to_json(tracks, camera_to_world, report).dump();
}

}  // namespace mereo::cognitive
