// mereo/cognitive/odometry.hpp: camera poses from the frames themselves, frame to frame, with
// OpenCV's RGB-D odometry (the contrib rgbd module: Steinbruecker et al.'s photometric and
// geometric alignment, RgbdICPOdometry), for inputs that carry no poses; corrected, when the
// frame's table plane and segments are given, against a map of the table and the upright
// cylinders and handles on it (landmarks.hpp): frame-to-frame ICP slides along an untextured table and
// accumulates drift, the landmarks do neither.
#pragma once

#include <memory>
#include <optional>

#include "mereo/core/camera.hpp"
#include "mereo/cognitive/landmarks.hpp"
#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::cognitive {

struct OdometryOptions {
  double min_depth = 0.3;   ///< metres: points nearer or farther are not used
  double max_depth = 4.0;
  double max_depth_difference = 0.07;  ///< metres: correspondences farther apart are dropped
  double max_jump = 0.1;      ///< metres: a motion this far from the last one is taken for a failed alignment
  double max_turn_deg = 10.0; ///< degrees: likewise
  LandmarkOptions landmarks;

  /// The options of the odometry node (the rest stay at their defaults).
  static const Fields<OdometryOptions>& fields();
};

inline const Fields<OdometryOptions>& OdometryOptions::fields() {
  using O = OdometryOptions;
  static const Fields<O> f = {
      field("max_depth", &O::max_depth, 0.5, 20, "farther points are not used, metres"),
      field("max_jump", &O::max_jump, 0.001, 100,
            "a motion this far from the last one (metres) is a failed alignment: the last motion is taken"),
      field("max_turn_deg", &O::max_turn_deg, 0.1, 180, "... or turned this far from it, degrees"),
  };
  return f;
}

/// Chains frame-to-frame motions into camera-to-world poses; the first frame is the world.
class Odometry {
 public:
  explicit Odometry(OdometryOptions options = {});
  ~Odometry();
  Odometry(Odometry&&) noexcept;
  Odometry& operator=(Odometry&&) noexcept;
  /// The pose of `frame` (camera to world). When the motion from the previous frame cannot be
  /// estimated (too few correspondences), the previous pose is kept and `lost()` counts it.
  /// With the frame's table plane (camera frame) and segments, the estimate is corrected against
  /// the landmark map (cognitive::locate) and the map grows by the frame's upright cylinders
  /// (when at least one of them matched a landmark, or the map has none yet).
  Pose update(const Frame& frame, const std::vector<Segment>& segments = {},
              const std::optional<TablePlane>& table = std::nullopt);
  std::size_t lost() const { return lost_; }
  /// Frames whose alignment moved too far from the last motion (`max_jump`, `max_turn_deg`): the
  /// last motion was taken instead.
  std::size_t jumps() const { return jumps_; }
  /// The last frame's correction (its matched and observed cylinders).
  const LandmarkFix& last_fix() const { return fix_; }
  const LandmarkMap& map() const { return map_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  OdometryOptions options_;
  std::size_t lost_ = 0, jumps_ = 0;
  LandmarkFix fix_;
  LandmarkMap map_;
};

}  // namespace mereo::cognitive
