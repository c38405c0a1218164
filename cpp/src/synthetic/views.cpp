#include "mereo/synthetic/scene.hpp"

namespace mereo::synthetic {

Pose orbit_view(const Scene& scene, int frame_index, const SceneOptions& options) {
  return orbit_pose(scene.look_at, scene.camera_distance, scene.camera_elevation_deg,
                    scene.camera_azimuth_deg + frame_index * options.orbit_step_deg);
}

}  // namespace mereo::synthetic
