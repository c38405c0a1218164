// mereo/core/image.hpp: the one dense image type that every layer shares.
//
// An Image<T, C> is H x W pixels of C interleaved channels of T, row-major and contiguous.
// Copies are shallow (they share the buffer, like cv::Mat); clone() makes a deep copy.
// The buffer is a std::shared_ptr so that Python can hold it through a NumPy array
// without copying (see cpp/pybind/bind_core.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace mereo {

template <typename T, int C>
class Image {
 public:
  using value_type = T;
  static constexpr int channels = C;

  Image() = default;
  /// A new image of rows x cols pixels, every value set to `fill`.
  Image(int rows, int cols, T fill = T{}) : rows_(rows), cols_(cols) {
    if (rows < 0 || cols < 0) throw std::invalid_argument("Image: negative size");
    data_ = std::shared_ptr<T[]>(new T[size()]);
    std::fill(data_.get(), data_.get() + size(), fill);
  }
  /// Wraps an existing buffer (shared ownership) of rows*cols*C values.
  Image(int rows, int cols, std::shared_ptr<T[]> buffer)
      : rows_(rows), cols_(cols), data_(std::move(buffer)) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  bool empty() const { return rows_ == 0 || cols_ == 0 || !data_; }
  /// Number of scalar values (rows * cols * channels).
  std::size_t size() const { return std::size_t(rows_) * std::size_t(cols_) * C; }
  std::size_t pixels() const { return std::size_t(rows_) * std::size_t(cols_); }

  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  T* ptr(int r, int c) { return data_.get() + (std::size_t(r) * cols_ + c) * C; }
  const T* ptr(int r, int c) const { return data_.get() + (std::size_t(r) * cols_ + c) * C; }
  T& operator()(int r, int c, int ch = 0) { return ptr(r, c)[ch]; }
  const T& operator()(int r, int c, int ch = 0) const { return ptr(r, c)[ch]; }
  bool same_size(int rows, int cols) const { return rows_ == rows && cols_ == cols; }
  template <typename U, int D>
  bool same_size(const Image<U, D>& o) const { return rows_ == o.rows() && cols_ == o.cols(); }

  const std::shared_ptr<T[]>& buffer() const { return data_; }

  Image clone() const {
    Image out;
    out.rows_ = rows_;
    out.cols_ = cols_;
    if (data_) {
      out.data_ = std::shared_ptr<T[]>(new T[size()]);
      std::copy(data_.get(), data_.get() + size(), out.data_.get());
    }
    return out;
  }

 private:
  int rows_ = 0;
  int cols_ = 0;
  std::shared_ptr<T[]> data_;
};

/// 8-bit RGB colour (channel order R, G, B).
using ColorImage = Image<std::uint8_t, 3>;
/// Depth in metres along the optical axis; NaN where there is no measurement.
using DepthImage = Image<float, 1>;
/// Organized point cloud: XYZ in metres per pixel, camera frame, NaN where missing.
using Cloud = Image<float, 3>;
/// The range any depth sensor measures, in metres: values outside (0.1 mm, 1 km), NaN, infinite
/// or denormal, count as missing, so extreme data never reaches an algorithm's arithmetic.
inline constexpr float kMinRange = 1e-4f, kMaxRange = 1e3f;
/// A measured depth: within the sensor range.
inline bool valid_depth(float z) { return z >= kMinRange && z <= kMaxRange; }
/// A measured point of a Cloud (a pointer to its x, y, z): in front of the camera, every
/// coordinate within the sensor range (NaN fails every comparison).
inline bool valid_point(float x, float y, float z) {
  // & rather than &&: no branch, so that loops over rows of points vectorize
  return (z >= kMinRange) & (z <= kMaxRange) & (std::abs(x) <= kMaxRange) & (std::abs(y) <= kMaxRange);
}
inline bool valid_point(const float* p) { return valid_point(p[0], p[1], p[2]); }
/// Per-pixel unit normals, camera frame, oriented towards the camera, NaN where undefined.
using NormalMap = Image<float, 3>;
/// Integer labels per pixel (object ids, part ids, dataset labels); 0 = none.
using LabelImage = Image<std::uint32_t, 1>;

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

}  // namespace mereo
