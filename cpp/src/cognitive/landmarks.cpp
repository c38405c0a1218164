// The camera's pose from the table plane and the upright cylinders and rings on it (see landmarks.hpp).
#include "mereo/cognitive/landmarks.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Geometry>

namespace mereo::cognitive {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A motion in the table's plane: w = R(theta) c + t.
struct Planar {
  double theta = 0.0;
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  Eigen::Vector2d apply(const Eigen::Vector2d& c) const { return Eigen::Rotation2Dd(theta) * c + t; }
};

/// A frame's point may be a landmark: the same class, radii that agree.
bool same_kind(const PlanarPoint& p, const Landmark& l, const LandmarkOptions& o) {
  return p.cls == l.cls && std::abs(p.radius - l.radius) <= o.radius_tolerance + 0.1 * std::max(p.radius, l.radius);
}

/// The landmark each point lands on under `g` (-1: none), and how many do.
int matches(const std::vector<PlanarPoint>& points, const std::vector<Landmark>& landmarks, const Planar& g,
            const LandmarkOptions& o, std::vector<int>* which = nullptr) {
  int n = 0;
  if (which) which->assign(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d w = g.apply(points[i].xy);
    double best = o.match_distance;
    int k = -1;
    for (std::size_t j = 0; j < landmarks.size(); ++j) {
      const double e = (landmarks[j].xy - w).norm();
      if (e < best && same_kind(points[i], landmarks[j], o)) best = e, k = int(j);
    }
    if (k >= 0) {
      ++n;
      if (which) (*which)[i] = k;
    }
  }
  return n;
}

/// The planar motion that best carries the matched points onto their landmarks (2-D Procrustes,
/// weighted by the points' weights); with `turn`, only the slide is fitted.
Planar fit(const std::vector<PlanarPoint>& points, const std::vector<Landmark>& landmarks, const std::vector<int>& which,
           std::optional<double> turn = std::nullopt) {
  Eigen::Vector2d cm = Eigen::Vector2d::Zero(), lm = Eigen::Vector2d::Zero();
  double n = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (which[i] >= 0) {
      const double w = points[i].weight;
      cm += w * points[i].xy, lm += w * landmarks[std::size_t(which[i])].xy, n += w;
    }
  cm /= n, lm /= n;
  double s = 0, c = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (which[i] < 0) continue;
    const Eigen::Vector2d p = points[i].xy - cm, q = landmarks[std::size_t(which[i])].xy - lm;
    c += points[i].weight * (q.x() * p.x() + q.y() * p.y());
    s += points[i].weight * (q.y() * p.x() - q.x() * p.y());
  }
  Planar g;
  g.theta = turn ? *turn : std::atan2(s, c);
  g.t = lm - Eigen::Rotation2Dd(g.theta) * cm;
  return g;
}

double angle_difference(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

Pose planar_pose(const Planar& g) {
  Pose G = Pose::Identity();
  G.linear() = Eigen::AngleAxisd(g.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  G.translation() = Eigen::Vector3d(g.t.x(), g.t.y(), 0.0);
  return G;
}

TablePlane in_world(const TablePlane& plane, const Pose& camera_to_world) {
  TablePlane w;
  w.normal = camera_to_world.linear() * plane.normal;
  w.d = plane.d - w.normal.dot(camera_to_world.translation());
  return w;
}

}  // namespace

Pose table_from(const TablePlane& plane) {
  const Eigen::Vector3d z = plane.normal.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z * z.x();
  if (x.norm() < 1e-3) x = Eigen::Vector3d::UnitY() - z * z.y();
  x.normalize();
  Pose A = Pose::Identity();
  A.linear().row(0) = x.transpose();
  A.linear().row(1) = z.cross(x).transpose();
  A.linear().row(2) = z.transpose();
  A.translation() = Eigen::Vector3d(0, 0, plane.d);  // so that z = the height above the plane
  return A;
}

std::vector<PlanarPoint> landmark_points(const std::vector<Segment>& segments, const TablePlane& plane,
                                         const LandmarkOptions& o) {
  std::vector<PlanarPoint> out;
  const Pose A = table_from(plane);
  const double cos_tilt = std::cos(o.max_tilt_deg * kPi / 180.0);
  for (const auto& s : segments) {
    if (const auto* ring = s.get_if<shapes::Torus>()) {
      // a handle (features/handle.hpp): its ring's centre dropped onto the table
      if (s.inliers < o.min_ring_inliers || !o.handle.plausible(s)) continue;
      const Eigen::Vector3d foot = ring->center - plane.normal * (plane.normal.dot(ring->center) + plane.d);
      out.push_back({(A * foot).head<2>(), ring->major_radius, s.cls(), o.ring_weight});
      continue;
    }
    const auto* c = s.get_if<shapes::Cylinder>();
    if (!c || s.inward || s.inliers < o.min_inliers) continue;
    if (c->radius < o.min_radius || c->radius > o.max_radius) continue;
    const double along = plane.normal.dot(c->axis);
    if (std::abs(along) < cos_tilt) continue;
    // where the axis meets the table
    const Eigen::Vector3d foot = c->point - c->axis * ((plane.normal.dot(c->point) + plane.d) / along);
    out.push_back({(A * foot).head<2>(), c->radius, s.cls(), 1.0});
  }
  return out;
}

LandmarkFix locate(const LandmarkMap& map, const TablePlane& plane, const std::vector<Segment>& segments,
                   const Pose& guess, const LandmarkOptions& o) {
  LandmarkFix fix;
  fix.camera_to_world = guess;
  if (!map.table) return fix;
  // is the frame's plane the map's table, under the guess?
  const TablePlane seen = in_world(plane, guess);
  const double angle = std::acos(std::clamp(seen.normal.dot(map.table->normal), -1.0, 1.0)) * 180.0 / kPi;
  const Eigen::Vector3d foot = guess * Eigen::Vector3d(-plane.d * plane.normal);
  if (angle > o.max_plane_angle_deg || std::abs(map.table->normal.dot(foot) + map.table->d) > o.max_plane_offset)
    return fix;
  fix.plane = true;
  const Pose Aw = table_from(*map.table), Ac = table_from(plane);
  // the guess as a planar motion (its tilt and height are replaced by the plane's)
  const Pose M = Aw * guess * Ac.inverse();
  Planar g0;
  g0.theta = std::atan2(M.linear()(1, 0), M.linear()(0, 0));
  g0.t = M.translation().head<2>();

  const auto points = landmark_points(segments, plane, o);
  const auto& L = map.landmarks;
  fix.observed = int(points.size());
  // candidates: the guess and every motion two matched pairs give; most matches wins, then the
  // one nearest the guess (a symmetric arrangement matches several ways)
  auto distance = [&](const Planar& g) { return (g.t - g0.t).norm() + 0.5 * angle_difference(g.theta, g0.theta); };
  Planar best = g0;
  int best_n = matches(points, L, g0, o);
  double best_d = 0.0;
  for (std::size_t i1 = 0; i1 < points.size(); ++i1)
    for (std::size_t i2 = i1 + 1; i2 < points.size(); ++i2) {
      const Eigen::Vector2d dc = points[i2].xy - points[i1].xy;
      if (dc.norm() < 0.03) continue;
      for (std::size_t j1 = 0; j1 < L.size(); ++j1) {
        if (!same_kind(points[i1], L[j1], o)) continue;
        for (std::size_t j2 = 0; j2 < L.size(); ++j2) {
          if (j2 == j1 || !same_kind(points[i2], L[j2], o)) continue;
          const Eigen::Vector2d dl = L[j2].xy - L[j1].xy;
          if (std::abs(dl.norm() - dc.norm()) > 2 * o.match_distance) continue;
          Planar g;
          g.theta = std::atan2(dl.y(), dl.x()) - std::atan2(dc.y(), dc.x());
          g.t = 0.5 * (L[j1].xy + L[j2].xy) - Eigen::Rotation2Dd(g.theta) * (0.5 * (points[i1].xy + points[i2].xy));
          const int n = matches(points, L, g, o);
          const double d = distance(g);
          if (n > best_n || (n == best_n && d < best_d)) best = g, best_n = n, best_d = d;
        }
      }
    }
  std::vector<int> which;
  fix.matched = matches(points, L, best, o, &which);
  if (fix.matched >= 2) {
    for (int it = 0; it < 3; ++it) {  // refit to all matches; the matches may change once
      const Planar g = fit(points, L, which);
      std::vector<int> w2;
      if (matches(points, L, g, o, &w2) < fix.matched) break;
      best = g;
      if (w2 == which) break;
      which = w2;
    }
  }
  // the turn: two axes fix it; rings, fitted less precisely, only bound the guess's (it stays
  // within `ring_turn_tolerance_deg` of theirs); one point leaves it to the guess. Then the slide.
  int axes = 0;
  for (std::size_t i = 0; i < points.size(); ++i) axes += which[i] >= 0 && points[i].cls == PrimitiveClass::of<shapes::Cylinder>();
  if (fix.matched >= 1 && axes < 2) {
    double turn = g0.theta;
    if (fix.matched >= 2) {
      const double d = std::remainder(best.theta - g0.theta, 2 * kPi), tolerance = o.ring_turn_tolerance_deg * kPi / 180.0;
      if (std::abs(d) > tolerance) turn += d - std::copysign(tolerance, d);
    }
    best = fit(points, L, which, turn);
  }
  fix.camera_to_world = Aw.inverse() * planar_pose(best) * Ac;
  return fix;
}

void add_to_map(LandmarkMap& map, const TablePlane& plane, const std::vector<Segment>& segments,
                const Pose& camera_to_world, const LandmarkOptions& o) {
  if (!map.table) map.table = in_world(plane, camera_to_world);
  const Pose M = table_from(*map.table) * camera_to_world * table_from(plane).inverse();
  for (const auto& p : landmark_points(segments, plane, o)) {
    const Eigen::Vector2d w = (M * Eigen::Vector3d(p.xy.x(), p.xy.y(), 0.0)).head<2>();
    Landmark* near = nullptr;
    double best = o.match_distance;
    for (auto& l : map.landmarks) {
      const double e = (l.xy - w).norm();
      if (e < best && same_kind(p, l, o)) best = e, near = &l;
    }
    if (!near) {
      map.landmarks.push_back({w, p.radius, p.cls, 1});
      continue;
    }
    // a running mean that keeps following slowly (at most 20 views' weight)
    const double a = 1.0 / std::min(near->views + 1, 20);
    near->xy += a * (w - near->xy);
    near->radius += a * (p.radius - near->radius);
    ++near->views;
  }
}

}  // namespace mereo::cognitive
