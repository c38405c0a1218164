// mereo/features/edges.hpp: 2-D primitives of the colour image, the edge modality's segments:
// straight lines and elliptical arcs (shapes/line.hpp, shapes/arc.hpp) fitted to the edge chains
// of signal/edges.hpp, with the colours on both sides and, where the frame has depth there, the
// 3-D segment or circle they lie on.
//
// Each chain is cut into straight pieces that stay within split_tolerance_px of their chord
// (Douglas-Peucker). Runs of consecutive pieces that turn the same way, by at most max_turn_deg
// each, are grown into an ellipse (Fitzgibbon's direct least squares, cv::fitEllipseDirect) for
// as long as the chain's points stay within the arc tolerances of it; an arc that spans at least
// min_arc_span_deg of its ellipse is kept. The other pieces of at least min_line_px are lines
// (total least squares). Lifting takes, at each edge pixel, the nearest point within
// lift_window_px (the occluding side of a depth edge) and fits a 3-D line (a circle: a plane, then
// a circle in it) to those points, kept when they fit within lift_tolerance * z.
#pragma once

#include <vector>

#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/signal/edges.hpp"

namespace mereo::features {

struct EdgePrimitiveOptions {
  signal::EdgeOptions edges;         ///< the edge chains
  double split_tolerance_px = 1.0;   ///< a straight piece stays this close to its chord
  double min_line_px = 15;           ///< shorter straight pieces are no line
  double arc_tolerance_px = 0.7;     ///< RMS distance of an arc's points to its ellipse
  double max_arc_error_px = 2.0;     ///< ... and the largest
  double min_arc_span_deg = 60;      ///< an arc covers at least this much of its ellipse
  double max_turn_deg = 60;          ///< an arc's consecutive pieces turn by at most this
  double min_minor_px = 3;           ///< an ellipse's smallest semi-axis
  double side_offset_px = 3;         ///< where the colours on either side are sampled
  bool lift = true;                  ///< fit 3-D lines and circles where the frame has depth
  int lift_window_px = 2;            ///< a pixel's depth comes from the nearest point this close
  double lift_tolerance = 0.01;      ///< RMS of the lifted points about their 3-D fit, metres at 1 m (x z)

  static const Fields<EdgePrimitiveOptions>& fields();
};

inline const Fields<EdgePrimitiveOptions>& EdgePrimitiveOptions::fields() {
  using O = EdgePrimitiveOptions;
  static const Fields<O> f = concat(
      nested(&O::edges, signal::EdgeOptions::fields()),
      Fields<O>{
          field("split_tolerance_px", &O::split_tolerance_px, 0.1, 20, "a straight piece's distance to its chord, px"),
          field("min_line_px", &O::min_line_px, 2, 100000, "shortest line, pixels"),
          field("arc_tolerance_px", &O::arc_tolerance_px, 0.05, 20, "RMS distance of an arc's points to its ellipse, px"),
          field("max_arc_error_px", &O::max_arc_error_px, 0.1, 50, "largest distance of an arc's points to its ellipse, px"),
          field("min_arc_span_deg", &O::min_arc_span_deg, 1, 360, "least share of its ellipse an arc covers, degrees"),
          field("max_turn_deg", &O::max_turn_deg, 1, 179, "largest turn between an arc's consecutive pieces, degrees"),
          field("min_minor_px", &O::min_minor_px, 0.5, 10000, "an arc's ellipse's least semi-axis, pixels"),
          field("side_offset_px", &O::side_offset_px, 1, 50, "distance of the side colour samples from the edge, px"),
          field("lift", &O::lift, "fit 3-D lines and circles where the frame has depth"),
          field("lift_window_px", &O::lift_window_px, 0, 10, "half-size of the window a pixel takes its depth from"),
          field("lift_tolerance", &O::lift_tolerance, 1e-4, 1, "RMS about a lifted fit, metres at 1 m (grows with z)"),
      });
  return f;
}

/// Lines and arcs of `chains` (of `color`'s edges), arcs first, then lines, each with its edge
/// pixels (`pixels`, `inliers`) and side colours; lifted to 3-D with `cloud` (organized, the size
/// of `color`; null: none is) where options.lift says. Ids are 0.. in the output's order.
/// Deterministic. Throws InputError on options out of range or a cloud of another size.
std::vector<Segment> fit_edge_primitives(const std::vector<signal::EdgeChain>& chains, const ColorImage& color,
                                         const Cloud* cloud, const EdgePrimitiveOptions& options = {});

/// detect_edges and fit_edge_primitives on a frame's colour image, lifted with the frame's cloud
/// (its own, or its depth back-projected). Throws InputError when the frame has no colour.
std::vector<Segment> detect_edge_primitives(const Frame& frame, const EdgePrimitiveOptions& options = {});

}  // namespace mereo::features
