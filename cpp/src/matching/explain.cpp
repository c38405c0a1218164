// Accepted objects must explain their region; what none explains is an unknown object (see
// mereo/matching/explain.hpp).
#include "mereo/matching/explain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mereo/features/regions.hpp"

namespace mereo::matching {
namespace {

struct Grid {
  const Cloud& cloud;
  int H, W;
  Eigen::Vector3d p(int i) const {
    const float* q = cloud.ptr(i / W, i % W);
    return {q[0], q[1], q[2]};
  }
};

/// Whether x lies within `tol` of the surface of a part: an axial one's wall (within its extent),
/// a sphere, a torus, with its normal (when there is one) within acos(min_cos) of the surface's.
/// Planes and free-form regions explain only their own pixels, and so do an axial part's end
/// discs: a lid counted so made the flat top of a rounded box explain it.
bool near_part(const Segment& s, const Eigen::Vector3d& x, double tol, const float* normal, double min_cos) {
  Eigen::Vector3d n;
  double dist = 0;
  const auto wall = [&](const auto& c) {  // an axial part's wall, within its extent
    return std::abs(c.axis.dot(x - c.point)) > c.height / 2 + tol ? INFINITY : c.signed_distance(x, &n);
  };
  if (const auto* c = s.get_if<shapes::Cylinder>()) {
    dist = wall(*c);
  } else if (const auto* k = s.get_if<shapes::Cone>()) {
    dist = wall(*k);
  } else if (s.is<shapes::Sphere>() || s.is<shapes::Torus>()) {
    dist = s.signed_distance(x, &n);
  } else {
    return false;
  }
  if (std::abs(dist) > tol) return false;
  return !normal || !std::isfinite(normal[0]) ||
         std::abs(n.dot(Eigen::Map<const Eigen::Vector3f>(normal).cast<double>())) >= min_cos;
}

/// Whether x lies inside a vessel `s` open at its upper end (an outer cylinder, seen from
/// outside; its rim is the end towards `up`), seen through its opening: within its radius of the
/// axis, below its rim by `tol` and
/// above its foot, on a line of sight that crosses the rim's plane within the rim. A mug's inside
/// (its far inner wall, its inner bottom) is often no part of its own (an inner wall too short or
/// too noisy to fit), yet it is the mug's; a lid or the flat top of a box lies on the rim's
/// plane, not below it, and the faces of a box a cylinder was fitted about are seen through its
/// wall, not its opening.
bool inside_opening(const Segment& s, const Eigen::Vector3d& x, const Eigen::Vector3d& up, double tol) {
  const auto* c = s.get_if<shapes::Cylinder>();
  if (!c || s.inward) return false;
  Eigen::Vector3d a = c->axis.normalized();
  if (a.dot(up) < 0) a = -a;  // towards the rim
  const double h = c->height / 2, along = a.dot(x - c->point);
  if (along > h - tol || along < -h) return false;
  if ((x - c->point - a * along).norm() >= c->radius) return false;
  // where the line of sight from the camera (the origin) crosses the rim's plane
  const double ax = a.dot(x);
  if (!(ax != 0)) return false;
  const double t = (a.dot(c->point) + h) / ax;  // (the ray: t x)
  if (!(t > 0) || !(t < 1)) return false;
  const Eigen::Vector3d q = t * x - c->point;
  return (q - a * a.dot(q)).norm() < c->radius;
}

}  // namespace

void explain_regions(std::vector<RecognizedObject>& objects, const std::vector<Segment>& segments,
                     const Cloud& cloud, const extension::SupportPlane& plane, const InterpretOptions& o,
                     const NormalMap* normals) {
  const int H = cloud.rows(), W = cloud.cols();
  if (!plane.roi.same_size(cloud)) return;  // no region of interest: nothing to check against
  const Grid g{cloud, H, W};
  const std::size_t N = std::size_t(H) * std::size_t(W);
  const auto in_roi = [&](int i) { return plane.roi.data()[i] != 0; };

  // the pixels of every accepted object's parts
  std::vector<int> owner(N, -1);
  std::vector<std::vector<int>> pixels(objects.size());
  std::vector<bool> free_form(objects.size(), false);  // made of free-form regions only
  for (std::size_t a = 0; a < objects.size(); ++a) {
    if (!objects[a].accepted) continue;
    for (const auto& part : objects[a].parts)
      for (int i : segments.at(std::size_t(part.second)).pixels) pixels[a].push_back(i);
    std::sort(pixels[a].begin(), pixels[a].end());
    pixels[a].erase(std::unique(pixels[a].begin(), pixels[a].end()), pixels[a].end());
    // a free-form region holds the primitives fitted to it: it does not stop their objects'
    // regions (a cylinder on a detergent bottle's band must still explain the whole bottle)
    free_form[a] = std::all_of(objects[a].parts.begin(), objects[a].parts.end(), [&](const auto& part) {
      return segments.at(std::size_t(part.second)).template is<shapes::Region>();
    });
    if (!free_form[a])
      for (int i : pixels[a]) owner[std::size_t(i)] = int(a);
  }

  // each object's footprint on the table, all the way up from its foot: a primitive fitted to a
  // band of a free-form object leaves the rest of it above unexplained (a ball about the object
  // would reach far over the top of a tin a tall jar stands on; what it stands on is not it)
  const Pose& T = plane.world_from_camera;
  const Eigen::Vector3d up = T.linear().transpose() * Eigen::Vector3d::UnitZ();  // (camera frame)
  struct Footprint {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();     // of its pixels
    Eigen::Vector2d body = Eigen::Vector2d::Zero();  // its first part's centre (on its axis)
    double radius = 0, foot = INFINITY, top = -INFINITY;
  };
  std::vector<Footprint> fp(objects.size());
  for (std::size_t a = 0; a < objects.size(); ++a) {
    if (!objects[a].accepted || pixels[a].empty()) continue;
    std::vector<Eigen::Vector3d> world;
    for (int i : pixels[a]) world.push_back(T * g.p(i));
    Footprint& f = fp[a];
    for (const auto& w : world) f.c += w.head<2>(), f.foot = std::min(f.foot, w.z()), f.top = std::max(f.top, w.z());
    f.c /= double(world.size());
    for (const auto& w : world) f.radius = std::max(f.radius, (w.head<2>() - f.c).norm());
    f.body = (T * segments.at(std::size_t(objects[a].parts.front().second)).origin()).head<2>();
  }
  const auto reject = [&](std::size_t a, const std::string& why) {
    objects[a].accepted = false;
    objects[a].rejected = why;
    for (int i : pixels[a]) owner[std::size_t(i)] = -1;
  };
  // each object's region: connected to its pixels, within its extent (plus reach) of its centre,
  // not another object's; its coverage is its own pixels' share
  std::vector<int> mark(N, -1), region_of(N, -1);
  int stamp = 0;
  for (std::size_t a = 0; a < objects.size(); ++a) {
    if (!objects[a].accepted || pixels[a].empty()) continue;
    // two objects do not fill one place: of two whose bodies' centres lie within the larger
    // footprint and whose heights overlap by half the lower one, the later (weaker) goes (a bowl
    // matched twice, round on its outside and conical on its inside; a band's pixels lie off
    // its body's centre, hence the bodies')
    std::size_t same = 0;
    for (const Footprint& fa = fp[a]; same < a; ++same) {
      const Footprint& fb = fp[same];
      const double overlap = std::min(fa.top, fb.top) - std::max(fa.foot, fb.foot);
      if (objects[same].accepted && (fa.body - fb.body).norm() < std::max(fa.radius, fb.radius) &&
          overlap > 0.5 * std::min(fa.top - fa.foot, fb.top - fb.foot))
        break;
    }
    if (same < a) {
      reject(a, "in the place of a " + objects[same].model + " that scores higher");
      continue;
    }
    const Eigen::Vector2d c = fp[a].c;
    const double radius = fp[a].radius, foot = fp[a].foot;
    // reach: what the parts missed beside the object (a handle's root, a rim); but beside its
    // foot is what it stands on (a tin's lid under a jar), not it
    const auto region = features::connected_region(cloud, pixels[a], o.depth_jump, mark, stamp++, [&](int j) {
      if (owner[std::size_t(j)] == int(a)) return true;
      if (!in_roi(j) || owner[std::size_t(j)] >= 0) return false;
      const Eigen::Vector3d w = T * g.p(j);
      const double d = (w.head<2>() - c).norm();
      return w.z() >= foot - o.reach && d <= radius + o.reach && (d <= radius || w.z() >= foot + o.reach);
    });
    // the region's pixels near the object's parts count with its own (noisy depth)
    std::size_t explained = pixels[a].size();
    const double min_cos = std::cos(o.surface_normal_deg * M_PI / 180);
    if (o.surface_tolerance > 0 && !free_form[a])  // (free-form regions explain only their own pixels)
      for (int j : region) {
        if (owner[std::size_t(j)] == int(a)) continue;
        const Eigen::Vector3d x = g.p(j);
        const double tol = o.surface_tolerance * std::clamp(x.z() * x.z(), 1.0, 2.0);
        const float* normal = normals ? normals->ptr(j / W, j % W) : nullptr;
        const bool near = std::any_of(objects[a].parts.begin(), objects[a].parts.end(), [&](const auto& part) {
          const Segment& s = segments.at(std::size_t(part.second));
          const double within = std::max(tol, o.surface_residual_factor * s.residual);
          return near_part(s, x, within, normal, min_cos) || (o.open_tops && inside_opening(s, x, up, within));
        });
        explained += near;
      }
    // its parts' pixels must explain min_coverage of the region, or with those near them
    // min_surface_coverage (noisy depth: the tolerant share, the stricter test)
    const double n = double(std::max<std::size_t>(1, region.size()));
    const double own = double(pixels[a].size()) / n;
    objects[a].coverage = double(explained) / n;
    // a free-form region is its object's whole region; one that explains less was cut (at a
    // silhouette) from something larger: a part of it (a drill's grip), not an object
    const double min_coverage = free_form[a] ? o.min_free_form_coverage : o.min_coverage;
    if (own < min_coverage && (free_form[a] || objects[a].coverage < o.min_surface_coverage)) {
      char why[200];
      std::snprintf(why, sizeof why,
                    "explains %.0f%% of its region (%zu of %zu pixels; at least %.0f%%), %.0f%% with the pixels near it "
                    "(at least %.0f%%): not a %s",
                    100 * own, pixels[a].size(), region.size(), 100 * min_coverage, 100 * objects[a].coverage,
                    100 * o.min_surface_coverage, objects[a].model.c_str());
      reject(a, why);
    } else {
      for (int i : region) region_of[std::size_t(i)] = int(a);
    }
  }
  std::vector<Footprint> kept;  // the accepted objects' places
  for (std::size_t a = 0; a < objects.size(); ++a)
    if (objects[a].accepted && !pixels[a].empty()) kept.push_back(fp[a]);
  // accepted objects first, as interpret lists them (ids and excludes renumbered)
  std::stable_partition(objects.begin(), objects.end(), [](const RecognizedObject& r) { return r.accepted; });
  std::vector<int> new_id(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k)
    if (objects[k].id >= 0 && objects[k].id < int(objects.size())) new_id[std::size_t(objects[k].id)] = int(k);
  for (auto& r : objects) {
    r.id = new_id[std::size_t(r.id)];
    for (int& e : r.excludes) e = new_id[std::size_t(e)];
    std::sort(r.excludes.begin(), r.excludes.end());
  }

  if (o.min_unknown_pixels <= 0) return;
  const Eigen::Matrix3d R = T.linear();
  const features::FacesCamera faces(cloud, normals, o.max_grazing_deg);
  const auto free = [&](int j) { return in_roi(j) && region_of[std::size_t(j)] < 0 && faces(j); };
  for (auto& region : features::connected_regions(cloud, o.depth_jump, o.min_unknown_pixels, free)) {
    RecognizedObject::Region r;
    r.box = {W, H, -1, -1};
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    Eigen::Vector2d at = Eigen::Vector2d::Zero();  // on the table
    double low = INFINITY, high = -INFINITY;       // above the table
    double top = 0;                                // up: from the table to the region's top
    for (int j : region) {
      r.box[0] = std::min(r.box[0], j % W), r.box[1] = std::min(r.box[1], j / W);
      r.box[2] = std::max(r.box[2], j % W), r.box[3] = std::max(r.box[3], j / W);
      const Eigen::Vector3d x = g.p(j);
      r.centroid += x;
      const Eigen::Vector3d w = R * x;
      lo = lo.cwiseMin(w), hi = hi.cwiseMax(w);
      const Eigen::Vector3d t = w + T.translation();  // T * x: the footprints' frame
      at += t.head<2>(), low = std::min(low, t.z()), high = std::max(high, t.z());
      top = std::max(top, plane.height(x));
    }
    at /= double(region.size());
    // what lies in an accepted object's place is more of it (the outer wall under a conical
    // bowl's inside, a pitcher's lid), not an unknown object
    if (std::any_of(kept.begin(), kept.end(), [&](const Footprint& f) {
          // (overlapping in height, not stacked: a tin a jar stands on touches only its foot)
          const double overlap = std::min(high, f.top) - std::max(low, f.foot);
          return (at - f.body).norm() < f.radius + o.reach && overlap > std::min(o.reach, 0.5 * (high - low));
        }))
      continue;
    r.centroid /= double(region.size());
    r.size = hi - lo;
    r.size.z() = top;
    r.indices = std::move(region);
    RecognizedObject u;
    u.id = int(objects.size());
    u.model = "unknown";
    u.rejected = "no model explains it";
    u.region = r;
    objects.push_back(std::move(u));
  }
}

}  // namespace mereo::matching
