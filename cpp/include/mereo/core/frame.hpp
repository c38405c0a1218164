// mereo/core/frame.hpp: one RGB-D frame, the unit that flows through a graph.
#pragma once

#include <optional>
#include <string>

#include "mereo/core/camera.hpp"
#include "mereo/core/image.hpp"

namespace mereo {

/// An RGB-D frame: 8-bit colour and depth in metres of the same size, registered,
/// with the intrinsics that project the depth.
struct Frame {
  std::string id;          ///< frame name ("0003"), unique within a sequence
  std::string source;      ///< the file or generator it came from
  double timestamp = 0.0;  ///< seconds; the sequence's clock (0 when unknown)
  Intrinsics intrinsics;
  ColorImage color;        ///< H x W x 3, RGB; may be empty when the source has none
  DepthImage depth;        ///< H x W metres, NaN where missing
  std::optional<Pose> pose;  ///< camera-to-world, when the source knows it
  /// The pose's world z points against gravity (the renderer's, a TUM groundtruth as mereo has
  /// always taken it); false where the source says its world is arbitrary (7-Scenes/3DMatch
  /// poses from SLAM): the support plane then finds "up" from the data.
  bool gravity_aligned = true;
  /// XYZ per pixel as the source gave it (PCD files); empty when it is to be computed
  /// from depth and intrinsics (see extension::back_project).
  Cloud cloud;
  /// Per-pixel labels from the source (the mOSD label field); empty when it has none.
  LabelImage labels;

  int rows() const { return depth.rows(); }
  int cols() const { return depth.cols(); }
  /// Throws std::invalid_argument (naming `source`) if the images disagree in size,
  /// the depth is missing or the intrinsics are not positive.
  void validate() const;
};

}  // namespace mereo
