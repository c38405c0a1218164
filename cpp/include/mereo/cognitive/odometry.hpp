// mereo/cognitive/odometry.hpp: camera poses from the frames themselves, frame to frame, with
// OpenCV's RGB-D odometry (the contrib rgbd module: Steinbruecker et al.'s photometric and
// geometric alignment, RgbdICPOdometry), for inputs that carry no poses.
#pragma once

#include <memory>
#include <optional>

#include "mereo/core/camera.hpp"
#include "mereo/core/frame.hpp"

namespace mereo::cognitive {

struct OdometryOptions {
  double min_depth = 0.3;   ///< metres: points nearer or farther are not used
  double max_depth = 4.0;
  double max_depth_difference = 0.07;  ///< metres: correspondences farther apart are dropped
};

/// Chains frame-to-frame motions into camera-to-world poses; the first frame is the world.
class Odometry {
 public:
  explicit Odometry(OdometryOptions options = {});
  ~Odometry();
  Odometry(Odometry&&) noexcept;
  Odometry& operator=(Odometry&&) noexcept;
  /// The pose of `frame` (camera to world). When the motion from the previous frame cannot be
  /// estimated (too few correspondences), the previous pose is kept and `lost()` counts it.
  Pose update(const Frame& frame);
  std::size_t lost() const { return lost_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  OdometryOptions options_;
  std::size_t lost_ = 0;
};

}  // namespace mereo::cognitive
