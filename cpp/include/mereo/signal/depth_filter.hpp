// mereo/signal/depth_filter.hpp: per-image depth preprocessing with no outside knowledge (the
// signal layer): an edge-preserving filter of Kinect-type depth.
#pragma once

#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"

namespace mereo::signal {

struct DepthFilterOptions {
  /// Pixels: the window is (2 * radius + 1)^2.
  int radius = 2;
  /// Spatial Gaussian sigma, pixels.
  double sigma_space = 1.5;
  /// Range sigma at 1 m, metres; it grows with z^2 like the axial noise of structured-light
  /// sensors (Khoshelham and Elberink 2012: sigma_z ~ 1.4 mm * z^2): sigma_r(z) = sigma_depth * z^2.
  double sigma_depth = 0.004;
  /// A neighbour further than depth_change_factor * z from the centre never contributes (depth
  /// jumps are kept sharp, as in the normals' discontinuity test).
  double depth_change_factor = 0.02;

  /// The options of the filter_depth node and Python function.
  static const Fields<DepthFilterOptions>& fields();
};

inline const Fields<DepthFilterOptions>& DepthFilterOptions::fields() {
  using O = DepthFilterOptions;
  static const Fields<O> f = {
      field("radius", &O::radius, 1, 10, "window half-size, pixels"),
      field("sigma_space", &O::sigma_space, 0.1, 20, "spatial sigma, pixels"),
      field("sigma_depth", &O::sigma_depth, 1e-5, 0.1, "range sigma at 1 m, metres (grows with z^2)"),
      field("depth_change_factor", &O::depth_change_factor, 1e-4, 1, "neighbours further than this times z are ignored"),
  };
  return f;
}

/// Bilateral filter of a depth image (metres, NaN = missing): each valid pixel becomes the
/// weighted mean of the valid neighbours in its window, with a Gaussian weight on the pixel
/// distance and one on the depth difference whose width grows with depth; neighbours across a
/// depth jump are ignored. Missing pixels stay missing (no hole filling). Parallel over rows
/// (oneTBB). Throws InputError on options out of range.
DepthImage filter_depth(const DepthImage& depth, const DepthFilterOptions& options = {});

/// The frame with its depth filtered. When the frame carries its own cloud (PCD files), each
/// point moves along its viewing ray to the filtered depth, so the cloud stays consistent.
Frame filter_depth(const Frame& frame, const DepthFilterOptions& options = {});

}  // namespace mereo::signal
