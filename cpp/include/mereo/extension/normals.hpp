// mereo/extension/normals.hpp: per-pixel surface normals of organized clouds.
#pragma once

#include <string>

#include "mereo/core/image.hpp"

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
};

/// Unit normals per pixel of an organized cloud (metres, camera frame), oriented towards the
/// camera (dot(n, p) < 0), NaN where the point is missing or no plane is defined. Windows never
/// cross a depth discontinuity. Parallel over row blocks (oneTBB). Throws InputError on a bad
/// option (window even or < 3, factor <= 0).
NormalMap estimate_normals(const Cloud& cloud, const NormalOptions& options = {});

/// "fast" or "covariance"; throws InputError naming the value otherwise.
NormalMethod normal_method(const std::string& name);

}  // namespace mereo::extension
