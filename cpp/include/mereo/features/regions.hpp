// mereo/features/regions.hpp: free-form regions, the objects that are no primitive. What no
// accepted object explains above the support, connected over 8-neighbours without a depth jump
// and apart at silhouettes (matching/explain.hpp: the unknown objects), is described as a segment
// of class `region` (shapes/region.hpp): the upright box that holds it and how narrow its top is.
// Models name it where an object's shape is free-form (a squeeze bottle: a slender region with a
// narrow top); the find_regions node appends them to the primitives for a second matching.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "mereo/core/image.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"

namespace mereo::features {

struct RegionOptions {
  double min_height = 0.02;     ///< lower regions (a card, a lid on the table) are none, metres
  double neck_share = 1.0 / 6;  ///< the top share of the height whose width is the `neck`

  static const Fields<RegionOptions>& fields();
};

inline const Fields<RegionOptions>& RegionOptions::fields() {
  using O = RegionOptions;
  static const Fields<O> f = {
      field("min_height", &O::min_height, 0, 10, "least height of a region above the support, metres"),
      field("neck_share", &O::neck_share, 0.01, 1, "the top share of the height measured for the neck"),
  };
  return f;
}

/// The region of `pixels` (indices v * width + u of `cloud`'s valid points) standing on `plane`,
/// as a segment of class region with those pixels and their mean colour (when `color` is given);
/// nullopt when it is lower than min_height or has fewer than 10 points. Deterministic.
std::optional<Segment> describe_region(const Cloud& cloud, const extension::SupportPlane& plane,
                                       std::vector<int> pixels, const RegionOptions& options = {},
                                       const ColorImage* color = nullptr);

/// The cosine of the angle between pixel i's normal and its ray back to the camera: 1 face-on,
/// 0 at a silhouette; NaN without a normal.
inline double facing_cos(const Cloud& cloud, const NormalMap& normals, int i) {
  const int W = cloud.cols();
  const float* n = normals.ptr(i / W, i % W);
  const float* p = cloud.ptr(i / W, i % W);
  const double r = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
  return -(double(n[0]) * p[0] + double(n[1]) * p[1] + double(n[2]) * p[2]) / r;
}

/// The pixels reachable from `seeds` over 8-neighbours that are valid, pass `enter(j)` and lie
/// within depth_jump times the depth of the pixel they are reached from. `mark` (one entry per
/// pixel) records the visited ones with `stamp`: regions grown with one stamp do not overlap.
template <class Enter>
std::vector<int> connected_region(const Cloud& cloud, const std::vector<int>& seeds, double depth_jump,
                                  std::vector<int>& mark, int stamp, Enter enter) {
  const int H = cloud.rows(), W = cloud.cols();
  const auto valid = [&](int i) { return valid_point(cloud.ptr(i / W, i % W)); };
  std::vector<int> out, stack;
  for (int i : seeds)
    if (mark[std::size_t(i)] != stamp && valid(i)) mark[std::size_t(i)] = stamp, stack.push_back(i);
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    out.push_back(i);
    const int v = i / W, u = i % W;
    const float zi = cloud.ptr(v, u)[2];
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du) {
        const int vv = v + dv, uu = u + du;
        if ((!dv && !du) || vv < 0 || vv >= H || uu < 0 || uu >= W) continue;
        const int j = vv * W + uu;
        if (mark[std::size_t(j)] == stamp || !valid(j) || !enter(j)) continue;
        if (std::abs(cloud.ptr(vv, uu)[2] - zi) > depth_jump * zi) continue;
        mark[std::size_t(j)] = stamp;
        stack.push_back(j);
      }
  }
  return out;
}

/// The regions of the pixels where `free(i)` holds, each grown by connected_region from its
/// first pixel (row-major order), those with at least min_pixels pixels. Deterministic.
template <class Free>
std::vector<std::vector<int>> connected_regions(const Cloud& cloud, double depth_jump, int min_pixels, Free free) {
  const std::size_t N = std::size_t(cloud.rows()) * std::size_t(cloud.cols());
  std::vector<int> mark(N, -1);
  std::vector<std::vector<int>> out;
  for (std::size_t s = 0; s < N; ++s) {
    if (mark[s] == 0 || !free(int(s))) continue;
    auto region = connected_region(cloud, {int(s)}, depth_jump, mark, 0, free);
    if (int(region.size()) >= min_pixels) out.push_back(std::move(region));
  }
  return out;
}

/// The objects standing in `roi` as regions (what explain_regions reports as unknown where no
/// object is accepted): its pixels connected without a depth jump (depth_jump times the depth)
/// and, with `normals`, apart at silhouettes (pixels seen at more than max_grazing_deg to their
/// ray join none); regions of at least min_pixels pixels, each sorted.
std::vector<std::vector<int>> object_regions(const Cloud& cloud, const extension::Mask& roi, const NormalMap* normals,
                                             double depth_jump = 0.02, double max_grazing_deg = 75,
                                             int min_pixels = 800);

}  // namespace mereo::features
