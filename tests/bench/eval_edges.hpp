// Ground truth of the edge modality, shared by bench_edges and the tests: the outline pixels of
// labelled objects (the renderer's object labels, a real frame's mask) where the colour image
// shows them, and the share of those that a set of detected edge pixels reaches.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "mereo/core/image.hpp"
#include "mereo/core/segment.hpp"

namespace mereo::bench {

/// Pixels (v * W + u) of a label that `keep` accepts with a 4-neighbour of another label, where
/// the two pixels' colours differ by at least `min_contrast` (RGB distance, 0-1): an outline a
/// person sees in the colour image.
template <class Keep>
std::vector<int> outline_pixels(const LabelImage& labels, const ColorImage& color, Keep keep, double min_contrast = 0.1) {
  const int W = labels.cols(), H = labels.rows();
  std::vector<int> out;
  for (int v = 1; v < H - 1; ++v)
    for (int u = 1; u < W - 1; ++u) {
      const auto l = labels.ptr(v, u)[0];
      if (!keep(l)) continue;
      for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        if (labels.ptr(v + dv, u + du)[0] == l) continue;
        const std::uint8_t* a = color.ptr(v, u);
        const std::uint8_t* b = color.ptr(v + dv, u + du);
        const double d = std::sqrt(double((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                          (a[2] - b[2]) * (a[2] - b[2]))) / 255;
        if (d >= min_contrast) {
          out.push_back(v * W + u);
          break;
        }
      }
    }
  return out;
}

/// The pixels of `segments` (their `pixels`) as a CV_8U mask of rows x cols, 255 on them.
inline cv::Mat segment_mask(const std::vector<Segment>& segments, int rows, int cols) {
  cv::Mat m(rows, cols, CV_8U, cv::Scalar(0));
  for (const auto& s : segments)
    for (int i : s.pixels) m.data[i] = 255;
  return m;
}

/// The share of `truth` pixels within `r` pixels (a square window) of a non-zero pixel of `hit`
/// (CV_8U, the image's size); 0 when truth is empty.
inline double outline_recall(const std::vector<int>& truth, const cv::Mat& hit, int r = 2) {
  if (truth.empty()) return 0;
  cv::Mat near;
  cv::dilate(hit, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1)));
  std::size_t n = 0;
  for (int i : truth) n += near.at<std::uint8_t>(i / hit.cols, i % hit.cols) != 0;
  return double(n) / double(truth.size());
}

}  // namespace mereo::bench
