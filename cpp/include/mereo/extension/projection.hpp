// mereo/extension/projection.hpp: depth image <-> organized cloud.
#pragma once

#include "mereo/core/frame.hpp"

namespace mereo::extension {

/// Back-projects a depth image (metres, NaN = missing) to an organized XYZ cloud in the
/// camera frame: x = (u - cx) z / fx, y = (v - cy) z / fy. Non-positive depth is NaN.
Cloud back_project(const DepthImage& depth, const Intrinsics& K);

/// The frame's cloud: the one the source gave, or the back-projection of its depth.
Cloud back_project(const Frame& frame);

/// Projects an organized cloud to a depth image (z per pixel, NaN where missing).
DepthImage cloud_depth(const Cloud& cloud);

/// Least-squares pinhole fit u = fx x/z + cx, v = fy y/z + cy to an organized cloud
/// (recovers the intrinsics of PCD files, which carry none). Throws InputError when the
/// cloud has fewer than 10 valid points. `max_residual_px` receives the worst residual.
Intrinsics fit_intrinsics(const Cloud& cloud, double* max_residual_px = nullptr);

}  // namespace mereo::extension
