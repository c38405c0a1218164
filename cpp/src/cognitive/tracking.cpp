// Tracking object hypotheses across frames (see tracking.hpp).
#include "mereo/cognitive/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "cognitive/json.hpp"
#include "features/shapes.hpp"

namespace mereo::cognitive {
namespace {

constexpr int kPerPart = 6;  // Kalman state per part: point (3), radius, minor radius, height

const Segment* body_of(const Observation& o) {
  for (const auto& [role, s] : o.parts)
    if (role == "body") return &s;
  return o.parts.empty() ? nullptr : &o.parts.front().second;
}

Eigen::Matrix<double, kPerPart, 1> params(const Segment& s) {
  Eigen::Matrix<double, kPerPart, 1> v;
  v << s.point, s.radius, s.minor_radius, s.height;
  return v;
}

/// The variance of a part's measured parameters: `measurement_noise` at 1 m for a fit to
/// `reference_inliers` pixels, growing as z^2 and falling as 1/sqrt(inliers).
double measurement_variance(const Segment& part, double distance, const TrackOptions& o) {
  const double inliers = part.inliers > 0 ? double(part.inliers) : o.reference_inliers;
  return std::pow(o.measurement_noise * distance * distance, 2) * o.reference_inliers / inliers;
}

/// `q`'s component across the unit `axis` (its distance from the axis is this one's norm).
Eigen::Vector3d across(const Eigen::Vector3d& q, const Eigen::Vector3d& axis) { return q - axis * axis.dot(q); }

/// The track's body (its first part).
const Segment& track_body(const Track& t) { return t.parts.front().world; }

bool same_body(const Segment& a, const Segment& b, const TrackOptions& o) {
  if (a.cls != b.cls) return false;
  const Eigen::Vector3d d = a.point - b.point;
  // cylinders: the centres' distance across the axis (the visible extent, hence the centre along
  // the axis, changes with the view); spheres and others: the centres' distance
  const double apart = a.cls == PrimitiveClass::Cylinder ? across(d, a.axis.normalized()).norm() : d.norm();
  return apart <= o.max_distance && std::abs(a.radius - b.radius) <= o.max_radius_difference;
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
/// body): its centre's offset from the body's axis across it, and its height along the axis.
/// The height is the centre's own, not relative to the body's centre: a cylinder's centre is the
/// middle of its visible extent, which moves when something hides its lower or upper part.
Eigen::Vector3d offset(const Segment& part, const Segment& body, const Eigen::Vector3d& axis) {
  return across(part.point - body.point, axis) + axis * axis.dot(part.point);
}

/// This view's points around the track's handles, fitted with those of the last views (world
/// frame): `drifted` for each handle whose ring would rather turn away from the body's axis.
double handle_evidence(Track& t, const DepthImage& depth, const Intrinsics& K, const Pose& camera_to_world,
                       const Pose& to_camera, const TrackOptions& o) {
  double delta = 0.0;
  const Segment& body = track_body(t);
  const Segment body_camera = transformed(body, to_camera);
  for (std::size_t p = 1; p < t.parts.size(); ++p) {
    TrackedPart& part = t.parts[p];
    if (part.world.cls != PrimitiveClass::Torus) continue;
    auto points = points_around(transformed(part.world, to_camera), body_camera, depth, K);
    if (points.size() < 30) continue;  // hidden, or out of view
    for (auto& q : points) q = camera_to_world * q;
    part.recent_points.push_back(std::move(points));
    if (int(part.recent_points.size()) > o.turn_views) part.recent_points.erase(part.recent_points.begin());
    if (part.recent_points.size() < 2) continue;
    std::vector<Eigen::Vector3d> all;
    for (const auto& v : part.recent_points) all.insert(all.end(), v.begin(), v.end());
    // the ring with the plane held (the tube too, if letting it go makes it implausibly fat)
    const Segment held = features::detail::refit_handle_or_hold(body, part.world, all, [](const Segment& s) {
      return s.minor_radius >= 0.002 && s.minor_radius <= 0.012 && s.radius >= 0.01 && s.radius <= 0.08;
    });
    const auto turn = features::detail::handle_turn(body, held, all);
    if (std::abs(turn.turn_deg) > o.max_handle_turn_deg && turn.rms_turned < 0.6 * turn.rms_held) delta += o.drifted;
  }
  return delta;
}

}  // namespace

std::vector<Eigen::Vector3d> points_around(const Segment& part, const Segment& body, const DepthImage& depth,
                                           const Intrinsics& K, double margin, std::size_t max_points) {
  std::vector<Eigen::Vector3d> out;
  const Eigen::Vector3d& c = part.point;
  if (depth.empty() || c.z() < 0.1) return out;
  const double reach = (part.cls == PrimitiveClass::Torus ? part.radius + part.minor_radius : part.radius) + margin;
  const Eigen::Vector3d a = body.axis.normalized();
  const Eigen::Vector2i c_px = K.pixel(c);
  const int u0 = c_px.x(), v0 = c_px.y();
  const int w = int(std::ceil(K.fx * reach / std::max(0.1, c.z() - reach)));
  for (int v = std::max(0, v0 - w); v <= std::min(depth.rows() - 1, v0 + w); ++v)
    for (int u = std::max(0, u0 - w); u <= std::min(depth.cols() - 1, u0 + w); ++u) {
      const double z = depth(v, u);
      if (!std::isfinite(z) || z <= 0) continue;
      const Eigen::Vector3d p = K.point(u, v, z);
      if ((p - c).norm() > reach || across(p - body.point, a).norm() < body.radius + margin) continue;
      out.push_back(p);
    }
  if (out.size() > max_points) {
    std::vector<Eigen::Vector3d> kept;
    features::detail::subsample_into(out, kept, max_points);
    out = std::move(kept);
  }
  return out;
}

Segment transformed(const Segment& s, const Pose& T) {
  Segment out = s;
  out.point = T * s.point;
  out.axis = T.linear() * s.axis;
  if (s.cls == PrimitiveClass::Plane) out.d = -out.axis.dot(out.point);
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
  if (part.cls == PrimitiveClass::Torus) {
    constexpr int kSamples = 36;
    const Eigen::Vector3d n = part.axis.normalized();
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const Eigen::Vector3d a = body.axis.normalized();
    for (int k = 0; k < kSamples; ++k) {
      const double phi = 2 * M_PI * k / kSamples;
      const Eigen::Vector3d p = part.point + part.radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
      // inside the body, or so close to its wall that the wall would pass for the part
      if (across(p - body.point, a).norm() < body.radius + part.minor_radius + tolerance) continue;
      points.push_back(p);
    }
    thickness = part.minor_radius;
    area = 2 * M_PI * part.radius / kSamples * 2 * part.minor_radius;
  } else {
    points.push_back(part.point);
    thickness = part.cls == PrimitiveClass::Plane ? 0.0 : part.radius;
    area = M_PI * part.radius * part.radius;
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
  // the observations in the world frame, and each one's distance (for its measurement noise)
  std::vector<Observation> world(observations);
  std::vector<double> distance(observations.size(), 1.0);
  for (std::size_t k = 0; k < world.size(); ++k) {
    for (auto& [role, s] : world[k].parts) s = transformed(s, camera_to_world);
    if (const Segment* b = body_of(observations[k])) distance[k] = std::max(0.3, b->point.z());
  }
  std::vector<bool> used(world.size(), false);
  const Pose to_camera = camera_to_world.inverse();
  // evidence in log-odds, bounded: at most `floor` against a hypothesis, 20 for it
  auto add_evidence = [&o](Track& t, double delta) { t.log_odds = std::clamp(t.log_odds + delta, o.floor, 20.0); };

  for (Track& t : tracks_) {
    ++t.age;
    for (auto& p : t.parts) p.segment = -1;
    // the observations of this track's body
    int support = -1;
    bool seen = false;
    for (std::size_t k = 0; k < world.size(); ++k) {
      const Segment* b = body_of(world[k]);
      if (!b || !same_body(*b, track_body(t), o)) continue;
      seen = true;
      if (world[k].accepted && world[k].model == t.model && (support < 0 || world[k].score > world[support].score))
        support = int(k);
    }
    t.seen = seen;
    // a handle's surroundings, whether or not this view found its body
    if (depth && !depth->empty()) {
      const double ring = handle_evidence(t, *depth, intrinsics, camera_to_world, to_camera, o);
      if (ring != 0) add_evidence(t, ring);
    }
    if (!seen) {
      if (t.log_odds > 0) t.log_odds *= o.decay;
      ++t.missed;
      continue;
    }
    t.missed = 0;
    if (support < 0) {
      // the body is there but not taken for this model: a contradiction, as strong as the view
      // shows the parts that would make the difference where the track holds them
      std::vector<std::string> roles;  // the parts of the model the view took the body for
      for (std::size_t k = 0; k < world.size(); ++k)
        if (world[k].accepted && body_of(world[k]) && same_body(*body_of(world[k]), track_body(t), o))
          for (const auto& [role, s] : world[k].parts) roles.push_back(role);
      Visibility v;
      if (depth && !depth->empty()) {
        const Segment body = transformed(track_body(t), to_camera);
        for (std::size_t p = 1; p < t.parts.size(); ++p)
          if (!t.parts[p].world.inward && std::find(roles.begin(), roles.end(), t.parts[p].role) == roles.end())
            v += part_visibility(transformed(t.parts[p].world, to_camera), body, *depth, intrinsics, o.depth_tolerance);
      }
      if (v.total() > 0) {
        const double shown = std::min(1.0, v.pixels / o.visible_pixels);
        if (shown > 0) add_evidence(t, o.contradicted * shown + (2 * v.through > v.seen() ? o.drifted * shown : 0.0));
        continue;
      }
      // without depth: a part behind the body and within its silhouette is hidden (a mug seen
      // with its handle at the back looks like a cup)
      const Eigen::Vector3d body = to_camera * track_body(t).point, ray = body.normalized();
      bool hidden = false;  // behind the body and within its silhouette
      for (std::size_t p = 1; p < t.parts.size(); ++p) {
        const Eigen::Vector3d rel = to_camera * t.parts[p].world.point - body;
        const double along = rel.dot(ray), lateral = (rel - ray * along).norm();
        hidden = hidden || (along > 0 && lateral < track_body(t).radius);
      }
      if (!hidden) add_evidence(t, o.contradicted);
      continue;
    }
    const Observation& ob = world[support];
    used[support] = true;
    ++t.hits;
    t.score = ob.score;
    double delta = o.support * (2 * ob.score - 1);
    const Segment& body_now = *body_of(ob);
    // parts: consistent with the body where the track holds them (fused), or drifted away
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
      const Eigen::Vector3d axis = track_body(t).axis.normalized();
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
    add_evidence(t, delta);
    // Kalman update of the parts that hold (static model: the prediction only adds process noise)
    for (std::size_t p = 0; p < t.parts.size(); ++p) {
      if (reanchor[p]) {
        t.x.segment<kPerPart>(kPerPart * p) = params(t.parts[p].world);
        t.P.segment<kPerPart>(kPerPart * p).setConstant(measurement_variance(t.parts[p].world, distance[support], o));
      }
      if (!fuse[p]) continue;
      const Segment& m = *fuse[p];
      const double r = measurement_variance(m, distance[support], o);
      auto z = params(m);
      Segment& w = t.parts[p].world;
      if (w.cls == PrimitiveClass::Cylinder) {
        // the centre along the axis follows the visible extent: only its position across the
        // axis is measured; along the axis the track keeps the newest view's
        const Eigen::Vector3d a = w.axis.normalized();
        const Eigen::Vector3d along = a * a.dot(z.head<3>() - t.x.segment<3>(kPerPart * p));
        t.x.segment<3>(kPerPart * p) += along;
      }
      for (int i = 0; i < kPerPart; ++i) {
        const int j = kPerPart * int(p) + i;
        const double q = i == 3 || i == 4 ? o.shape_noise : o.process_noise;  // radius, minor radius
        t.P(j) += q * q;
        const double gain = t.P(j) / (t.P(j) + r);
        t.x(j) += gain * (z(i) - t.x(j));
        t.P(j) *= 1 - gain;
      }
      // axes: a running mean, sign-aligned
      Eigen::Vector3d axis = m.axis.normalized();
      if (axis.dot(w.axis) < 0) axis = -axis;
      w.axis = (w.axis.normalized() * double(t.hits - 1) + axis).normalized();
      w.point = t.x.segment<3>(kPerPart * p);
      w.radius = t.x(kPerPart * p + 3);
      w.minor_radius = t.x(kPerPart * p + 4);
      w.height = t.x(kPerPart * p + 5);
      w.inliers = m.inliers;
    }
  }
  // drop what has been out of view too long (rejected hypotheses in view are held)
  std::vector<Track> kept;
  for (Track& t : tracks_) {
    if (t.missed > o.max_missed) {
      dropped_.push_back({t.id, frame_});
      continue;
    }
    kept.push_back(std::move(t));
  }
  tracks_ = std::move(kept);
  // new tracks from the accepted observations that no track took
  for (std::size_t k = 0; k < world.size(); ++k) {
    const Observation& ob = world[k];
    if (used[k] || !ob.accepted || !body_of(ob)) continue;
    bool taken = false;  // another track of the same model already holds this body
    for (const Track& t : tracks_) taken = taken || (t.model == ob.model && same_body(*body_of(ob), track_body(t), o));
    if (taken) continue;
    Track t;
    t.id = next_id_++;
    t.model = ob.model;
    t.log_odds = o.prior + o.support * (2 * ob.score - 1);
    t.hits = 1, t.seen = true, t.score = ob.score;
    // the body first, then the other parts
    std::vector<int> order(ob.parts.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::stable_partition(order.begin(), order.end(), [&](int i) { return ob.parts[std::size_t(i)].first == "body"; });
    t.x.resize(kPerPart * int(order.size()));
    t.P.resize(kPerPart * int(order.size()));
    for (std::size_t p = 0; p < order.size(); ++p) {
      const auto& [role, part] = ob.parts[std::size_t(order[p])];
      t.parts.push_back({role, part, segment_of(ob, order[p]), part, std::nullopt, {}});
      t.x.segment<kPerPart>(kPerPart * p) = params(part);
      t.P.segment<kPerPart>(kPerPart * p).setConstant(measurement_variance(part, distance[k], o));
    }
    tracks_.push_back(std::move(t));
  }
  std::sort(tracks_.begin(), tracks_.end(), [](const Track& a, const Track& b) { return a.id < b.id; });
  return tracks_;
}

namespace detail {

matching::detail::Json tracks_to_json(const std::vector<Track>& tracks, const Pose& camera_to_world, double report) {
  using matching::detail::Json;
  const Pose camera_from_world = camera_to_world.inverse();
  Json out = Json::array();
  for (const Track& t : tracks) {
    if (t.probability() < report) continue;
    Json o;
    o["id"] = out.size(), o["model"] = t.model, o["score"] = t.score, o["probability"] = t.probability();
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
