// mereo/features/handle.hpp: what a handle is, in one place. The detector's model-driven search
// for a mug's handle next to its body, the tracker's check of a handle across views and the
// landmarks' rings all read HandleOptions.
//
// A handle is, today, a torus whose ring plane holds its body's axis, outside the body's wall and
// within its height (Kasprzak et al.'s handle-on-body function; the mug model's ranges are in
// graphs/models/tabletop.yaml). The search (features/primitives.hpp: DetectOptions::handle):
//  1. the usable pixels near the body between its wall (radius + half the noise) and `max_reach`
//     beyond it, within its visible height less `foot_margin` (the table's edge pixels at its foot
//     are not a handle), are binned by azimuth about the axis (`bin_deg`);
//  2. the best azimuth windows (`window_deg`, at most `max_windows` that do not overlap) give a
//     ring plane each (through the axis, at the circular mean azimuth of their pixels);
//  3. a torus starting at the window's extent (tube `start_minor_radius`, ring radius = half its
//     height span, at least `min_start_radius`, outer edge at its farthest pixel) is refined by
//     Levenberg-Marquardt on the window's pixels standing at least `min_standoff` off the wall
//     (a geometric fit: the normals of a noisy 1 cm tube are poor), the ring first with the tube
//     held, trimmed `trim_rounds` times to the points within `trim_factor` epsilon, then the tube
//     too if it stays plausible;
//  4. the best hypothesis by its pixels (within epsilon, normal not turned past `min_facing_cos`,
//     largest group connected across gaps of `pixel_gap` pixels) is refined `refit_rounds` times;
//  5. it is no handle when its ring would rather turn its plane away from the body's axis (more
//     than `max_turn_deg`, with a residual under `turn_residual_ratio` of the held one: a ring
//     leaning on a jar).
//  6. it is no handle when its ring is centred inside the body and most of its pixels lie on the
//     body's wall (wall_patch: a grown stereo wall bent into a tube), or when a cone through the
//     body's points holds most of them and few stand beyond it (tapered_wall: a tapered cup's
//     wider rest of its wall).
// Where the depth shows no handle, its silhouette is looked for in the colour image (`from_colour`,
// detail::colour_handle in features/pixels.hpp): beside the body's limbs, in the body's colour and
// not the background's, shaped as a handle (reach, height span, a loop that does not fill its box);
// a torus in that plane, attached to the wall, stands for it. The plane is the limb's, or turned
// about the axis by up to 60 degrees either way (a handle seen obliquely), where then part of the
// silhouette has depth near that plane. Where neither shows it (`from_edges`, detail::edge_handle),
// its outline is looked for among the colour image's edges about the body: an edge chain that
// leaves a limb and comes back to it, standing off it as a handle does, with the body's colour on
// its inner side and, where that side has depth, depth near the axis (not an outline behind).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/shapes/cylinder.hpp"
#include "mereo/shapes/torus.hpp"

namespace mereo::features {

/// Every constant of what a handle is and how it is searched for.
struct HandleOptions {
  /// Look for a handle next to every cylinder that could be a body (top-down), and not for tori
  /// bottom-up.
  bool search_near_cylinders = true;
  double body_min_radius = 0.02;      ///< ... whose radius lies in this range (a goal narrows it)
  double body_max_radius = 0.08;
  double region_margin = 0.04;        ///< the search ball: the body's extent plus this, metres
  double small_cylinder_ratio = 0.5;  ///< a cylinder under this share of the body's radius in the
                                      ///< ball may be a wide handle's side: its pixels are offered
  double max_reach = 0.07;            ///< a handle's pixels stand at most this far off the wall
  double foot_margin = 0.003;         ///< ... and this far above the body's foot
  double bin_deg = 5.0;               ///< azimuth bins about the body's axis
  double window_deg = 25.0;           ///< the window of bins a handle fills
  int max_windows = 2;                ///< hypotheses (non-overlapping windows) per body
  double fit_half_width_deg = 15.0;   ///< the pixels a hypothesis is fitted to, about its azimuth
  double min_standoff = 0.008;        ///< ... that stand off the wall at least this (or epsilon)
  double start_minor_radius = 0.006;  ///< the tube radius a fit starts from
  double min_start_radius = 0.012;    ///< the least ring radius a fit starts from
  int trim_rounds = 2;                ///< ring refits to the points within trim_factor * epsilon
  double trim_factor = 2.0;
  int refit_rounds = 2;               ///< refits of the best hypothesis to its pixels
  double min_facing_cos = -0.5;       ///< a handle pixel's normal within 120 deg of the tube's
  int pixel_gap = 2;                  ///< a handle's pixels connect across gaps of this (noise)
  double normal_deviation_factor = 2; ///< the search's normal deviation, times the detector's
  double min_minor_radius = 0.0015;   ///< tube radius range of a handle (a noisy tube reads thin)
  double max_minor_radius = 0.012;
  double min_major_radius = 0.01;     ///< ring radius range of a handle (the tracker's check)
  double max_major_radius = 0.08;
  /// A ring that fits clearly better (residual under turn_residual_ratio of the held fit) with its
  /// plane turned more than this about the body's axis is no handle; degrees, 90 = no check.
  double max_turn_deg = 25.0;
  double turn_residual_ratio = 0.6;
  /// Where the depth shows no handle next to a body (no ring `beside` it), look for its
  /// silhouette beside the body in the colour image (detail::colour_handle: thin tubes beyond a
  /// metre lose their depth).
  bool from_colour = true;
  /// ... in the limbs' planes, and in those turned about the axis by up to this (a handle seen
  /// obliquely); degrees, 0 = the limbs' planes only.
  double colour_max_turn_deg = 60.0;
  /// Where neither shows it, look for its outline among the colour image's edges beside the body
  /// (detail::edge_handle: a handle in the background's colours, or crossing another object).
  bool from_edges = true;

  /// A handle's tube and ring radii are within the ranges (the tracker's refits).
  bool plausible(const Segment& t) const;

  /// t is plausible and its ring is centred beside `body`, at least half the body's radius off its
  /// axis (an attached ring's centre stands a ring radius less a tube radius beyond the wall; a
  /// ring about the axis is a fit to the wall, no handle), and spans no more than about the
  /// body's height (its diameter at most 2.5 cm over the fitted height).
  bool beside(const shapes::Cylinder& body, const Segment& t) const;

  /// x (camera frame) is where a handle of `body` may be: off its wall by more than `noise`
  /// (half the depth noise there) and at most max_reach, within its height less foot_margin.
  bool in_reach(const shapes::Cylinder& body, const Eigen::Vector3d& x, double noise) const;

  /// A segment found bottom-up next to a body that may be a piece of its handle, offered to the
  /// handle search (a D-shaped handle's curve taken for an inward cylinder or a sphere): curved,
  /// not an outer wall (a neighbouring body), under half the body's pixels, and at least
  /// `piece_in_reach` of its pixels in reach.
  double piece_in_reach = 0.7;

  /// The options the detect_primitives and track_objects nodes and Python expose (the rest are
  /// the definition of a handle, kept at their defaults).
  static const Fields<HandleOptions>& fields();
};

inline const Fields<HandleOptions>& HandleOptions::fields() {
  using O = HandleOptions;
  static const Fields<O> f = {
      field("handles_near_cylinders", &O::search_near_cylinders, "look for a torus next to every cylinder"),
      field("handle_body_min_radius", &O::body_min_radius, 0, 1, "... whose radius is at least this, metres"),
      field("handle_body_max_radius", &O::body_max_radius, 0, 1, "... and at most this"),
      field("handles_from_colour", &O::from_colour,
            "where the depth shows no handle, look for its silhouette beside the body in the colour image"),
      field("colour_handle_turn_deg", &O::colour_max_turn_deg, 0, 75,
            "... in planes turned from the limbs' about the body's axis by up to this (0: the limbs' planes only)"),
      field("handles_from_edges", &O::from_edges,
            "where neither the depth nor the silhouette shows a handle, look for its outline among the colour image's edges"),
      field("max_handle_turn_deg", &O::max_turn_deg, 0, 90,
            "a ring that fits better turned more than this from its body's axis is not a handle (90: no check)"),
  };
  return f;
}

/// A handle's torus refined to `points` about `body` by Levenberg-Marquardt on the geometric
/// distance, from `t0`, with its ring plane held through the body's axis (5 parameters: azimuth,
/// height, distance of the centre from the axis, ring radius, tube radius). Only the side of a
/// thin tube that faces the camera is seen; a free fit can then trade a tilted ring plane for a
/// fat tube, while with the plane held the tube radius is how far the points stand out of it.
/// With `fix_minor`, the tube radius stays t0's (on a far, noisy handle only the ring is well
/// determined). `body` is a cylinder, `t0` a torus.
/// A handle is attached: a ring whose tube's centre line would stay outside the wall is refitted
/// with it entering the wall by the tube radius (its distance from the axis = body radius + ring
/// radius - tube radius): noisy points of the outer arc alone otherwise give a small ring off the wall.
Segment refit_handle(const Segment& body, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                     bool fix_minor = false);

/// refit_handle with the tube free when that fit passes `plausible`, else with the tube held (a
/// fat tube can swallow a turned ring).
template <class Plausible>
Segment refit_handle_or_hold(const Segment& body, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                             Plausible plausible) {
  Segment free_fit = refit_handle(body, t0, points);
  return plausible(free_fit) ? free_fit : refit_handle(body, t0, points, true);
}

/// How a handle's ring plane would rather turn about the body's axis (0: it holds the axis, as a
/// handle's does; a ring leaning on a jar is turned): the fit of refit_handle (tube held) with the
/// turn free as well, against the fit with the plane held.
struct HandleTurn {
  double turn_deg = 0.0;    ///< the best turn, -90..90
  double rms_held = 0.0;    ///< the residual (metres) with the plane through the axis
  double rms_turned = 0.0;  ///< with the plane turned
  /// The ring turns away from the axis, clearly (HandleOptions::max_turn_deg, turn_residual_ratio).
  bool turned_away(const HandleOptions& o) const {
    return std::abs(turn_deg) > o.max_turn_deg && rms_turned < o.turn_residual_ratio * rms_held;
  }
};
HandleTurn handle_turn(const Segment& body, const Segment& t, const std::vector<Eigen::Vector3d>& points);

/// A torus found next to `body` that is a patch of the body's own wall, not its handle: its ring
/// centred inside the body and most of its points (its pixels') on the wall, within `tolerance(z)`
/// (wavy stereo depth bends a wall into a tube). A handle's ring is centred about the wall or
/// beyond (rendered mugs 0.96-1.6 radii off the axis, real ones 0.8-1.3; a real pitcher's torus
/// 0.4, but off the wall) and stands off the wall but at its roots.
template <class Tolerance>
bool wall_patch(const shapes::Cylinder& body, const Segment& t, const std::vector<Eigen::Vector3d>& points,
                Tolerance tolerance) {
  const auto* ring = t.get_if<shapes::Torus>();
  if (!ring || body.signed_distance(ring->center) >= 0) return false;
  std::size_t on_wall = 0;
  for (const auto& x : points) on_wall += std::abs(body.signed_distance(x)) <= tolerance(x.z());
  return 2 * on_wall > points.size();
}

/// A torus found next to `body` that is the rest of a tapered wall: the body's cylinder was fitted
/// to the part of a cone (a tapered cup) near its radius, and the wall beyond it, wider, was taken
/// for a tube. A line rho = r0 + k t (distance from the body's axis against the position along it)
/// fitted to the body's points and the torus's together is a cone through both; when it tapers by
/// at most kMaxTaperDeg and holds most of the torus's points within `tolerance(z)`, they are wall,
/// unless a quarter of them stand beyond twice that outside it: a handle's roots lie on the wall,
/// but its outer arc stands off it by up to the ring's diameter (rendered stereo 4512 and 5038,
/// Kinect-like 5049: true handles with 54%, 51% and 51% of their points on the line and 30-40%
/// beyond; the rests of tapered walls rejected on stereo 5000-5049: none beyond, but one 32%).
template <class Tolerance>
bool tapered_wall(const shapes::Cylinder& body, const std::vector<Eigen::Vector3d>& wall,
                  const std::vector<Eigen::Vector3d>& points, Tolerance tolerance) {
  constexpr double kMaxTaperDeg = 25;
  const Eigen::Vector3d a = body.axis.normalized();
  const auto t_rho = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d q = x - body.point;
    const double t = a.dot(q);
    return Eigen::Vector2d(t, (q - a * t).norm());
  };
  double n = 0, st = 0, sr = 0, stt = 0, str = 0;
  for (const auto* set : {&wall, &points})
    for (const auto& x : *set) {
      const Eigen::Vector2d p = t_rho(x);
      n += 1, st += p.x(), sr += p.y(), stt += p.x() * p.x(), str += p.x() * p.y();
    }
  const double var = stt - st * st / std::max(n, 1.0);
  if (points.empty() || !(var > 0)) return false;
  const double k = (str - st * sr / n) / var, r0 = (sr - k * st) / n;
  if (std::abs(k) > std::tan(kMaxTaperDeg * M_PI / 180)) return false;
  const double c = 1 / std::sqrt(1 + k * k);  // the distance from the line along its normal
  std::size_t on = 0, beyond = 0;
  for (const auto& x : points) {
    const Eigen::Vector2d p = t_rho(x);
    const double off = (p.y() - r0 - k * p.x()) * c, tol = tolerance(x.z());
    on += std::abs(off) <= tol;
    beyond += off > 2 * tol;
  }
  return 2 * on > points.size() && 4 * beyond < points.size();
}

}  // namespace mereo::features
