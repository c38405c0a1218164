// mereo/signal/register.hpp: depth from a second camera brought into the colour camera (the
// signal layer: before colour meets depth, every pixel's colour and depth must see one point).
#pragma once

#include "mereo/core/camera.hpp"
#include "mereo/core/image.hpp"

namespace mereo::signal {

/// The depth image of `camera` (its intrinsics, and its transform to the colour camera) as the
/// colour camera with intrinsics `color` and a rows x cols image sees it: each depth pixel's point
/// moved into the colour camera's frame and projected to its nearest pixel, the nearest point kept
/// where several meet (as OpenCV's rgbd::registerDepth without dilation; bench_edges compares
/// them). NaN where no point lands. The colour camera's lens distortion is not modelled. Throws InputError on invalid intrinsics, a non-rigid
/// transform or an empty size.
DepthImage register_depth(const DepthImage& depth, const DepthCamera& camera, const Intrinsics& color, int rows,
                          int cols);

}  // namespace mereo::signal
