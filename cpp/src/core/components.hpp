// The 4-connected components of a binary image, found on its horizontal runs of set pixels. A
// plane's inliers in a depth image are a few large regions: a row holds a few dozen runs where it
// holds hundreds of pixels, so that labelling runs costs a fraction of labelling pixels
// (cv::connectedComponents, which gives the same partition: tests/cpp/test_extension.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace mereo {

struct Components {
  int rows = 0, cols = 0;
  /// the runs, row by row and left to right: pixels [begin, end) of row `row`
  std::vector<int> row, begin, end;
  std::vector<int> label;          ///< component of each run, 0 .. count-1
  std::vector<std::size_t> area;   ///< pixels per component
  int count() const { return int(area.size()); }
};

/// The 4-connected components of the nonzero pixels of `mask` (CV_8U).
Components connected_components(const cv::Mat& mask);

/// 255 on the pixels of the components that `keep` marks (keep[label] != 0), 0 elsewhere.
cv::Mat draw_components(const Components& c, const std::vector<std::uint8_t>& keep);

/// For each component, whether any of its pixels is nonzero in `other` (CV_8U, same size).
std::vector<std::uint8_t> components_touching(const Components& c, const cv::Mat& other);

}  // namespace mereo
