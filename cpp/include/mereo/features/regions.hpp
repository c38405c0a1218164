// mereo/features/regions.hpp: free-form regions, the objects that are no primitive. What no
// accepted object explains above the support, connected over 8-neighbours without a depth jump
// and apart at silhouettes (matching/explain.hpp: the unknown objects), is described as a segment
// of class `region` (shapes/region.hpp): the upright box that holds it and how narrow its top is.
// Models name it where an object's shape is free-form (a squeeze bottle: a slender region with a
// narrow top); the find_regions node appends them to the primitives for a second matching.
#pragma once

#include <algorithm>
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

/// Whether a pixel faces the camera: seen at no more than max_grazing_deg between its normal and
/// its ray (at a silhouette a surface turns away, and what touches it behind joins it without a
/// depth jump). Every pixel does without normals (null, or of another size than the cloud).
class FacesCamera {
 public:
  FacesCamera(const Cloud& cloud, const NormalMap* normals, double max_grazing_deg)
      : cloud_(cloud), normals_(normals && normals->same_size(cloud) ? normals : nullptr),
        min_cos_(std::cos(max_grazing_deg * M_PI / 180)) {}
  bool operator()(int i) const {
    if (!normals_) return true;
    const int W = cloud_.cols();
    const float* n = normals_->ptr(i / W, i % W);
    const float* p = cloud_.ptr(i / W, i % W);
    const double r = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
    return -(double(n[0]) * p[0] + double(n[1]) * p[1] + double(n[2]) * p[2]) >= min_cos_ * r;  // (NaN: no)
  }

 private:
  const Cloud& cloud_;
  const NormalMap* normals_;
  double min_cos_;
};

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
/// first pixel (row-major order), those with at least min_pixels pixels, each sorted.
/// Deterministic.
template <class Free>
std::vector<std::vector<int>> connected_regions(const Cloud& cloud, double depth_jump, int min_pixels, Free free) {
  const std::size_t N = std::size_t(cloud.rows()) * std::size_t(cloud.cols());
  std::vector<int> mark(N, -1);
  std::vector<std::vector<int>> out;
  for (std::size_t s = 0; s < N; ++s) {
    if (mark[s] == 0 || !free(int(s))) continue;
    auto region = connected_region(cloud, {int(s)}, depth_jump, mark, 0, free);
    if (int(region.size()) < min_pixels) continue;
    std::sort(region.begin(), region.end());
    out.push_back(std::move(region));
  }
  return out;
}

/// The objects standing in `roi` as regions (what explain_regions reports as unknown where no
/// object is accepted): its pixels connected without a depth jump (depth_jump times the depth)
/// and, with `normals`, apart at silhouettes (pixels seen at more than max_grazing_deg to their
/// ray join none); regions of at least min_pixels pixels, each sorted. The tabletop graph's values
/// are InterpretOptions' depth_jump, max_grazing_deg and min_unknown_pixels.
std::vector<std::vector<int>> object_regions(const Cloud& cloud, const extension::Mask& roi, const NormalMap* normals,
                                             double depth_jump, double max_grazing_deg, int min_pixels);

}  // namespace mereo::features
