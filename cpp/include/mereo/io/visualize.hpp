// mereo/io/visualize.hpp: images people would rather see than read.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mereo/core/camera.hpp"
#include "mereo/core/image.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::io {

/// Depth as a false-colour image (turbo colour map between the 1st and 99th percentile of the
/// valid depth, near = red... far = blue); missing depth is black.
ColorImage colorize_depth(const DepthImage& depth);
/// Normals as colours: RGB = (n + 1) / 2 (x right red, y down green, towards the camera blue);
/// missing normals are black.
ColorImage colorize_normals(const NormalMap& normals);
/// Labels as distinct colours (0 is black).
ColorImage colorize_labels(const LabelImage& labels);
/// Images of the same height side by side (a gap of `gap` black pixels between them).
ColorImage hstack(const std::vector<ColorImage>& images, int gap = 4);
/// One object to draw: its label ("mug 0.91") and its parts (camera frame).
struct DrawnObject {
  std::string label;
  std::vector<Segment> parts;
  /// An object without parts (an unknown one): its image box (u0, v0, u1, v1), drawn in grey.
  std::optional<std::array<int, 4>> box;
};

/// The colour image with each object drawn over it: the projected outlines of its parts
/// (a cylinder's end circles and silhouette lines, a torus's ring and outer edge, a sphere's
/// outline; planes are not drawn) in a colour per object, and its label above it. Parts behind
/// the camera are skipped. Throws InputError on an empty image or invalid intrinsics.
ColorImage draw_objects(const ColorImage& color, const Intrinsics& intrinsics,
                        const std::vector<DrawnObject>& objects);

/// Writes an RGB image as PNG (or any format OpenCV knows by the file's extension).
void write_image(const std::string& path, const ColorImage& image);

}  // namespace mereo::io
