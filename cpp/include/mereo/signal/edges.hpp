// mereo/signal/edges.hpp: the edge image of a colour image (the signal layer): chains of connected
// edge pixels, each point moved to the sub-pixel maximum of the gradient across the edge.
// features/edges.hpp fits lines and elliptical arcs to them. The chains come from Canny's edges
// linked here (the default: bench_edges measured OpenCV's Edge Drawing, which walks chains from
// anchors along gradient ridges, Topal and Akinlar 2012, at 8-12 ms on textured real VGA frames),
// or from Edge Drawing itself (ximgproc).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"

namespace mereo::signal {

/// Where the edge pixels and their chains come from.
enum class EdgeMethod {
  /// Canny's non-maximum suppression and hysteresis (OpenCV) on our gradient, then the thin edge
  /// pixels linked into chains here, each walk going on to the neighbour that turns least.
  Canny,
  /// OpenCV's Edge Drawing (ximgproc): chains walked from anchors along gradient ridges.
  EdgeDrawing,
};

struct EdgeOptions {
  EdgeMethod method = EdgeMethod::Canny;
  /// Gradient magnitude (|gx| + |gy| of Sobel on 8-bit grey levels) below which no pixel is an
  /// edge (Canny: the low threshold; a chain holds a pixel of twice this).
  int gradient_threshold = 24;
  /// The threshold rises to this many times the image's median gradient magnitude where that is
  /// higher: on a textured or noisy image (wood grain, a real sensor's colour noise) the weak
  /// edges of the texture are not outlines. 0: the fixed threshold alone.
  double texture_factor = 2.5;
  /// Edge Drawing: an anchor (where a chain starts) exceeds its two neighbours across the edge by this much.
  int anchor_threshold = 8;
  /// Gaussian smoothing before the gradient, pixels.
  double sigma = 1.0;
  /// Shorter chains are dropped, pixels.
  int min_chain_px = 12;
  /// Move each point to the parabolic peak of the gradient magnitude across the edge.
  bool subpixel = true;

  static const Fields<EdgeOptions>& fields();
};

inline const Fields<EdgeOptions>& EdgeOptions::fields() {
  using O = EdgeOptions;
  static const Fields<O> f = {
      choice("method", &O::method, {{"canny", EdgeMethod::Canny}, {"edge_drawing", EdgeMethod::EdgeDrawing}},
             "where the edge chains come from: Canny's edges linked here, or Edge Drawing's"),
      field("gradient_threshold", &O::gradient_threshold, 1, 1020, "least gradient magnitude of an edge pixel"),
      field("texture_factor", &O::texture_factor, 0, 100, "the threshold rises to this times the median gradient"),
      field("anchor_threshold", &O::anchor_threshold, 0, 255, "Edge Drawing: how much an anchor exceeds its neighbours"),
      field("sigma", &O::sigma, 0.3, 10, "Gaussian smoothing before the gradient, pixels"),
      field("min_chain_px", &O::min_chain_px, 2, 100000, "shortest edge chain kept, pixels"),
      field("subpixel", &O::subpixel, "refine points to the gradient's sub-pixel peak across the edge"),
  };
  return f;
}

/// One chain of edge points in image coordinates (x right, y down, pixel centres at integers),
/// in the order they are connected.
struct EdgeChain {
  std::vector<Eigen::Vector2f> points;
};

/// The edge chains of an 8-bit RGB image, longest first. Deterministic. Throws InputError on an
/// empty image or options out of range.
std::vector<EdgeChain> detect_edges(const ColorImage& color, const EdgeOptions& options = {});

}  // namespace mereo::signal
