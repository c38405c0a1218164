// Scene relations (see mereo/cognitive/relations.hpp).
#include "mereo/cognitive/relations.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/plane2.hpp"
#include "mereo/core/error.hpp"

namespace mereo::cognitive {
namespace {

/// Where an object stands: heights above the support (metres) and its footprint in the
/// support's plane (2-D coordinates along e1, e2).
struct Placement {
  double lowest = 0, highest = 0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;  ///< the footprint's half extent across
};

/// The support's plane: footprints (Plane2) and heights above it.
struct Frame2 : mereo::detail::Plane2 {
  double d;
  Frame2(const Eigen::Vector3d& normal, double offset) : Plane2(normal), d(offset) {}
  double height(const Eigen::Vector3d& x) const { return up.dot(x) + d; }
};

std::optional<Placement> place(const PlacedObject& ob, const Frame2& f) {
  Placement p;
  if (!ob.parts.empty()) {
    p.lowest = std::numeric_limits<double>::infinity(), p.highest = -p.lowest;
    for (const Segment& s : ob.parts) {
      const double h = f.height(s.origin()), half = s.half_extent_along(f.up);
      if (!std::isfinite(h) || !std::isfinite(half)) continue;
      p.lowest = std::min(p.lowest, h - half), p.highest = std::max(p.highest, h + half);
    }
    const Segment& body = ob.parts.front();
    p.centre = f.of(body.origin());
    p.radius = std::max(body.half_extent_along(f.e1), body.half_extent_along(f.e2));
    if (!std::isfinite(p.lowest) || !std::isfinite(p.radius)) return std::nullopt;
    return p;
  }
  if (ob.box_centre && ob.box_size) {
    const double h = f.height(*ob.box_centre);
    p.lowest = h - 0.5 * ob.box_size->z(), p.highest = h + 0.5 * ob.box_size->z();
    p.centre = f.of(*ob.box_centre);
    p.radius = 0.5 * std::max(ob.box_size->x(), ob.box_size->y());
    return p;
  }
  return std::nullopt;
}

}  // namespace

std::vector<Relation> scene_relations(const std::vector<PlacedObject>& objects, const Eigen::Vector3d& normal,
                                      double d, const RelationOptions& o) {
  if (!normal.allFinite() || std::abs(normal.norm() - 1.0) > 1e-3 || !std::isfinite(d))
    throw InputError("scene relations: the support's normal must be a unit vector and d finite");
  const Frame2 f(normal, d);
  const std::size_t n = objects.size();
  std::vector<std::optional<Placement>> at(n);
  for (std::size_t i = 0; i < n; ++i) at[i] = place(objects[i], f);

  std::vector<Relation> out;
  // what each object rests on: the object whose top its foot meets (nearest), else the support
  std::vector<int> on(n, std::numeric_limits<int>::min());
  for (std::size_t a = 0; a < n; ++a) {
    if (!at[a]) continue;
    double best = o.on_gap;
    for (std::size_t b = 0; b < n; ++b) {
      if (b == a || !at[b]) continue;
      const double gap = std::abs(at[a]->lowest - at[b]->highest);
      // b is lower and holds a's footprint centre, and a's foot is clear of the support itself
      // by more than b's top is (not two bodies side by side of one height)
      if (gap <= best && at[b]->highest < at[a]->highest && at[b]->lowest < at[a]->lowest &&
          (at[a]->centre - at[b]->centre).norm() <= at[b]->radius)
        best = gap, on[a] = int(b);
    }
    if (on[a] < 0 && std::abs(at[a]->lowest) <= o.on_gap) on[a] = Relation::kSupport;
    if (on[a] != std::numeric_limits<int>::min())
      out.push_back({"on", objects[a].id, on[a] == Relation::kSupport ? Relation::kSupport : objects[std::size_t(on[a])].id});
  }
  // side by side on the same thing
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) {
      if (!at[a] || !at[b] || on[a] == std::numeric_limits<int>::min() || on[a] != on[b]) continue;
      const double gap = (at[a]->centre - at[b]->centre).norm() - at[a]->radius - at[b]->radius;
      if (gap <= o.next_to_gap) {
        const bool ordered = objects[a].id < objects[b].id;
        out.push_back({"next_to", ordered ? objects[a].id : objects[b].id, ordered ? objects[b].id : objects[a].id});
      }
    }
  // between the camera and another: nearer along the line from the camera's foot to the other,
  // and across that line by less than their footprints together
  const Eigen::Vector2d eye = f.of(Eigen::Vector3d::Zero());
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b || !at[a] || !at[b]) continue;
      const Eigen::Vector2d to_b = at[b]->centre - eye;
      const double dist = to_b.norm();
      if (dist < 1e-6) continue;
      const Eigen::Vector2d dir = to_b / dist, q = at[a]->centre - eye;
      const double along = q.dot(dir), across = std::abs(q.x() * dir.y() - q.y() * dir.x());
      if (along > 0 && along < dist - at[b]->radius && across < at[a]->radius + at[b]->radius)
        out.push_back({"in_front_of", objects[a].id, objects[b].id});
    }
  return out;
}

}  // namespace mereo::cognitive
