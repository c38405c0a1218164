// Scoring of detected primitives against ground truth, shared by bench_primitives and the
// feature-layer tests (tests/cpp/test_features.cpp):
//  - synthetic frames: the renderer's exact per-pixel part labels and part parameters;
//  - mOSD frames: the per-point object labels, with the "upright cylindrical objects" found by a
//    reference fit to the labelled points (a circle in the table plane, see mosd_cylinders()).
// A detection is attributed to the ground-truth part (object) that holds the majority of its
// inlier pixels; the fraction is its purity.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "mereo/core/image.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/synthetic/scene.hpp"

namespace mereo::bench {

inline double axis_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

/// The label holding most of the segment's pixels in `labels`, and that share (purity).
inline std::pair<std::uint32_t, double> majority_label(const Segment& s, const LabelImage& labels) {
  std::map<std::uint32_t, int> count;
  for (int i : s.pixels) ++count[labels.data()[i]];
  std::uint32_t best = 0;
  int n = 0;
  for (const auto& [l, c] : count)
    if (c > n) best = l, n = c;
  return {best, s.pixels.empty() ? 0.0 : double(n) / double(s.pixels.size())};
}

/// Totals over synthetic frames (see score_synthetic).
struct SyntheticScore {
  int frames = 0;
  int bodies = 0, bodies_found = 0;        ///< cylindrical bodies with >= min_body_pixels
  int handles = 0, handles_found = 0;      ///< mug handles with >= min_handle_pixels within 1.2 m
  int false_cylinders = 0, false_tori = 0;
  std::vector<double> radius_err_mm, axis_err_deg;  ///< of the found bodies
  /// ... and per found body its distance from the camera (m) and signed radius error (mm): a
  /// fit's bias shows as a mean that grows with distance.
  std::vector<std::pair<double, double>> radius_bias;

  /// Mean signed radius error (mm) of the found bodies whose distance is in [near, far); NAN if none.
  double mean_radius_bias_mm(double near, double far) const {
    double sum = 0;
    int n = 0;
    for (const auto& [d, e] : radius_bias)
      if (d >= near && d < far) sum += e, ++n;
    return n ? sum / n : NAN;
  }
  std::vector<double> handle_minor_err_mm;          ///< of the found handles
  std::vector<std::string> missed;                  ///< "seed:model:role (pixels)"

  double body_recall() const { return bodies ? double(bodies_found) / bodies : NAN; }
  double handle_recall() const { return handles ? double(handles_found) / handles : NAN; }
  double false_cylinders_per_frame() const { return frames ? double(false_cylinders) / frames : NAN; }
};

/// Scores one synthetic frame. A body (a part "body" of class cylinder with at least
/// `min_body_pixels` visible) is found when a detected cylinder has at least half of its
/// pixels on it; its radius and axis errors are those of the largest such cylinder. A handle
/// (a mug's "handle" with at least `min_handle_pixels` visible, its centre within
/// `max_handle_distance`) is found
/// when a detected torus has at least half of its pixels on it. A detected cylinder whose
/// pixels are mostly not on a cylindrical part, or whose radius is more than 1 cm off that
/// part's, is false; likewise a torus not mostly on a torus part.
inline void score_synthetic(const synthetic::GroundTruth& gt, const std::vector<Segment>& found, const std::string& tag,
                            SyntheticScore& acc, std::size_t min_body_pixels = 500, std::size_t min_handle_pixels = 150,
                            double max_handle_distance = 1.2) {
  ++acc.frames;
  std::map<std::uint32_t, const synthetic::PartTruth*> part_of;
  std::map<std::uint32_t, const synthetic::ObjectTruth*> object_of;
  for (const auto& o : gt.objects_truth)
    for (const auto& p : o.parts) part_of[p.label] = &p, object_of[p.label] = &o;
  std::map<std::uint32_t, const Segment*> best_cyl, best_torus;
  for (const Segment& s : found) {
    if (!s.is<shapes::Cylinder>() && !s.is<shapes::Torus>()) continue;
    const auto [label, purity] = majority_label(s, gt.parts);
    const auto it = part_of.find(label);
    const synthetic::PartTruth* p = it == part_of.end() ? nullptr : it->second;
    if (s.is<shapes::Cylinder>()) {
      const bool ok = p && purity >= 0.5 && p->camera.cls == "cylinder" && std::abs(s.size() - p->camera.radius) <= 0.01;
      if (!ok) {
        ++acc.false_cylinders;
        continue;
      }
      auto& b = best_cyl[label];
      if (!b || b->pixels.size() < s.pixels.size()) b = &s;
    } else {
      const bool ok = p && purity >= 0.5 && p->camera.cls == "torus";
      if (!ok) {
        ++acc.false_tori;
        continue;
      }
      auto& b = best_torus[label];
      if (!b || b->pixels.size() < s.pixels.size()) b = &s;
    }
  }
  for (const auto& o : gt.objects_truth)
    for (const auto& p : o.parts) {
      if (p.role == "body" && p.camera.cls == "cylinder" && p.visible_pixels >= min_body_pixels) {
        ++acc.bodies;
        const auto it = best_cyl.find(p.label);
        if (it == best_cyl.end()) {
          acc.missed.push_back(tag + ":" + o.model + ":body (" + std::to_string(p.visible_pixels) + " px)");
          continue;
        }
        ++acc.bodies_found;
        const auto& c = it->second->as<shapes::Cylinder>();
        acc.radius_err_mm.push_back(1000 * std::abs(c.radius - p.camera.radius));
        acc.radius_bias.emplace_back(p.camera.point.norm(), 1000 * (c.radius - p.camera.radius));
        acc.axis_err_deg.push_back(axis_angle_deg(c.axis, p.camera.axis));
      }
      if (o.model == "mug" && p.role == "handle" && p.visible_pixels >= min_handle_pixels &&
          p.camera.point.norm() <= max_handle_distance) {
        ++acc.handles;
        const auto it = best_torus.find(p.label);
        if (it == best_torus.end()) {
          acc.missed.push_back(tag + ":mug:handle (" + std::to_string(p.visible_pixels) + " px)");
          continue;
        }
        ++acc.handles_found;
        acc.handle_minor_err_mm.push_back(1000 * std::abs(it->second->as<shapes::Torus>().minor_radius - p.camera.minor_radius));
      }
    }
}

/// A circle fitted to 2-D points: algebraic least squares (Kasa), then Gauss-Newton on the
/// geometric distance; with `trim` > 0, points farther than `trim` from the circle are dropped
/// and the fit repeated (a handle beside a body).
struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0, rms = 0;
  std::size_t points = 0;
};

inline Circle fit_circle(std::vector<Eigen::Vector2d> pts, double trim = 0.0) {
  Circle out;
  for (int pass = 0; pass < (trim > 0 ? 4 : 1); ++pass) {
    if (pts.size() < 3) return out;
    Eigen::MatrixXd A(pts.size(), 3);
    Eigen::VectorXd b(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      A(k, 0) = pts[k].x(), A(k, 1) = pts[k].y(), A(k, 2) = 1;
      b(k) = -pts[k].squaredNorm();
    }
    const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
    Eigen::Vector2d c(-s(0) / 2, -s(1) / 2);
    double r = std::sqrt(std::max(0.0, c.squaredNorm() - s(2)));
    for (int it = 0; it < 30; ++it) {  // Gauss-Newton on |x - c| - r
      Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
      Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
      for (const auto& x : pts) {
        const Eigen::Vector2d d = x - c;
        const double len = std::max(1e-9, d.norm());
        const Eigen::Vector3d J(-d.x() / len, -d.y() / len, -1.0);
        JtJ += J * J.transpose(), Jtr += J * (len - r);
      }
      const Eigen::Vector3d step = JtJ.ldlt().solve(-Jtr);
      c += step.head<2>(), r += step(2);
      if (step.norm() < 1e-10) break;
    }
    double ss = 0;
    for (const auto& x : pts) ss += std::pow((x - c).norm() - r, 2);
    out = {c, r, std::sqrt(ss / pts.size()), pts.size()};
    if (trim > 0) {
      std::vector<Eigen::Vector2d> kept;
      for (const auto& x : pts)
        if (std::abs((x - c).norm() - r) <= trim) kept.push_back(x);
      if (kept.size() == pts.size()) break;
      pts = std::move(kept);
    }
  }
  return out;
}

/// The wall of an upright object: the points of `mask` (non-zero pixels) whose normal is within
/// 30 deg of the plane normal to `up`, in 2-D coordinates of that plane.
template <class Pred>
std::vector<Eigen::Vector2d> wall_points(const Cloud& cloud, const NormalMap& normals, const Eigen::Vector3d& up,
                                         Pred in_mask) {
  const Eigen::Vector3d e1 = up.unitOrthogonal(), e2 = up.cross(e1);
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < cloud.pixels(); ++i) {
    if (!in_mask(i)) continue;
    const float* p = cloud.data() + 3 * i;
    const float* n = normals.data() + 3 * i;
    if (!std::isfinite(p[2]) || !std::isfinite(n[0])) continue;
    const Eigen::Vector3d x(p[0], p[1], p[2]), nn(n[0], n[1], n[2]);
    if (std::abs(nn.dot(up)) > std::sin(30 * M_PI / 180)) continue;
    out.emplace_back(x.dot(e1), x.dot(e2));
  }
  return out;
}

/// An upright cylindrical object of an mOSD frame, found by the reference fit.
struct MosdCylinder {
  std::uint32_t object = 0;   ///< label / 10
  int side_pixels = 0;        ///< pixels of its wall (normal within 30 deg of horizontal)
  double radius = 0;          ///< of the reference circle, metres
  double rms_mm = 0;          ///< of the reference circle fit
};

/// The upright cylindrical objects of a labelled frame: for each object (label / 10 >= 2), its
/// wall points (wall_points) are fitted with a circle in the table plane (`up` = the table's
/// normal). An object is kept when its wall has at least `min_pixels` points, the circle's RMS
/// distance is at most 3 mm and its radius is 1.5-15 cm. The reference uses nothing of the
/// detector: only the labels, the points and their normals.
inline std::vector<MosdCylinder> mosd_cylinders(const Cloud& cloud, const NormalMap& normals, const LabelImage& labels,
                                                const Eigen::Vector3d& up, int min_pixels = 500) {
  std::map<std::uint32_t, int> objects;
  for (std::size_t i = 0; i < labels.pixels(); ++i)
    if (labels.data()[i] >= 20) objects[labels.data()[i] / 10] = 1;
  std::vector<MosdCylinder> out;
  for (const auto& [object, _] : objects) {
    const std::uint32_t id = object;
    const auto pts = wall_points(cloud, normals, up, [&](std::size_t i) { return labels.data()[i] / 10 == id && labels.data()[i] >= 20; });
    if (int(pts.size()) < min_pixels) continue;
    const Circle c = fit_circle(pts);
    if (c.rms <= 0.003 && c.radius >= 0.015 && c.radius <= 0.15)
      out.push_back({object, int(pts.size()), c.radius, 1000 * c.rms});
  }
  return out;
}

}  // namespace mereo::bench
