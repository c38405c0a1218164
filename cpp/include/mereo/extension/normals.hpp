// mereo/extension/normals.hpp: per-pixel surface normals of organized clouds.
#pragma once

#include <string>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"

namespace mereo::extension {

enum class NormalMethod {
  /// Least-squares tangents over a square window: t_u = sum du * p, t_v = sum dv * p (separable
  /// box passes, the smoothed-3D-gradient idea of Holzer et al. 2012), n = t_u x t_v.
  Fast,
  /// PCA of the window's points (smallest eigenvector of the covariance) from integral images
  /// (Holzer, Rusu, Dixon, Gedikli, Navab, "Adaptive neighborhood selection for real-time surface
  /// normal estimation from organized point cloud data using integral images", IROS 2012).
  Covariance
};

struct NormalOptions {
  NormalMethod method = NormalMethod::Fast;
  /// Pixels, odd (>= 3): the side of the square window.
  int window = 5;
  /// A depth jump between 4-neighbours larger than depth_change_factor * z breaks smoothing: no
  /// window crosses it (windows shrink near it; at the jump itself only the points within
  /// depth_change_factor * z of the centre's depth are used).
  double depth_change_factor = 0.02;
  /// Metres: beyond this depth the jump threshold grows as z^2 (depth_change_factor * z^2 /
  /// noise_depth) like the noise of structured-light sensors, so that a far wall's noise is not
  /// taken for discontinuities.
  double noise_depth = 2.0;
  /// Covariance: the window's side is window * reference_depth / z (odd, in [3, 2 * window + 1]),
  /// i.e. a constant metric size: it shrinks with depth. Off: the side is `window` everywhere.
  bool adaptive_window = true;
  /// Metres: the depth at which the adaptive window's side equals `window`.
  double reference_depth = 1.0;
  /// Fewest points a window must hold for a normal (else NaN).
  int min_points = 4;

  /// The options of the estimate_normals node and Python function.
  static const Fields<NormalOptions>& fields();
};

inline const Fields<NormalOptions>& NormalOptions::fields() {
  using O = NormalOptions;
  static const Fields<O> f = {
      choice("method", &O::method, {{"fast", NormalMethod::Fast}, {"covariance", NormalMethod::Covariance}},
             "fast: least-squares tangents; covariance: PCA through integral images"),
      field("window", &O::window, 3, 101, "window side in pixels (odd)"),
      field("depth_change_factor", &O::depth_change_factor, 1e-4, 1,
            "a depth jump larger than this times z breaks smoothing"),
      field("noise_depth", &O::noise_depth, 0.1, 100, "metres: beyond it the jump threshold grows as z^2 (sensor noise)"),
      field("adaptive_window", &O::adaptive_window, "covariance: the window shrinks with depth (constant metric size)"),
      field("reference_depth", &O::reference_depth, 0.1, 10, "metres: depth at which the adaptive window equals `window`"),
  };
  return f;
}

/// Unit normals per pixel of an organized cloud (metres, camera frame), oriented towards the
/// camera (dot(n, p) < 0), NaN where the point is missing or no plane is defined. Windows never
/// cross a depth discontinuity. Parallel over row blocks (oneTBB). Throws InputError on a bad
/// option (window even or < 3, factor <= 0).
NormalMap estimate_normals(const Cloud& cloud, const NormalOptions& options = {});

/// "fast" or "covariance"; throws InputError naming the value otherwise.
NormalMethod normal_method(const std::string& name);

}  // namespace mereo::extension
