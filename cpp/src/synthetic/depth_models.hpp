// Private to the synthetic renderer: the depth models that turn the exact depth into a
// camera's (the Kinect model is render.cpp's own loop; the stereo model is depth_stereo.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "mereo/synthetic/scene.hpp"
#include "raycast.hpp"

namespace mereo::synthetic::detail {

/// What the primary rays found, per pixel (row-major), and where they came from.
struct RenderedRays {
  const RenderScene& scene;
  const Intrinsics& K;
  const DepthImage& depth;            ///< exact depth, NaN where no surface
  const std::vector<float>& shade;    ///< cosine between the ray and the surface normal
  const std::vector<double>& ray_t;   ///< distance along the unit ray
  const std::vector<int>& hit_obj;    ///< index into scene.objects, -1: no surface
  std::uint64_t seed = 0;
  int frame = 0;
};

/// The active-stereo camera's depth (StereoModel) of the exact depth: `out` (same size) gets
/// the measured depth, NaN where there is none. Deterministic per seed and frame; parallel.
void stereo_depth(const RenderedRays& rays, const StereoModel& model, DepthImage& out);

}  // namespace mereo::synthetic::detail
