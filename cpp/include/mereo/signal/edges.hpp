// mereo/signal/edges.hpp: the edge image of a colour image (the signal layer): chains of connected
// edge pixels, each point moved to the sub-pixel maximum of the gradient across the edge. The
// chains come from OpenCV's Edge Drawing (ximgproc; Topal and Akinlar 2012), which links edge
// pixels by walking from anchors along gradient ridges: one pass, no hysteresis, chains of single
// pixels. features/edges.hpp fits lines and elliptical arcs to them.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"

namespace mereo::signal {

struct EdgeOptions {
  /// Gradient magnitude (|gx| + |gy| of Sobel on 8-bit grey levels) below which no pixel is an edge.
  int gradient_threshold = 24;
  /// An anchor (where a chain starts) exceeds its two neighbours across the edge by this much.
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
      field("gradient_threshold", &O::gradient_threshold, 1, 1020, "least gradient magnitude of an edge pixel"),
      field("anchor_threshold", &O::anchor_threshold, 0, 255, "how much an anchor exceeds its neighbours"),
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
