#include "mereo/io/visualize.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Geometry>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mereo/core/error.hpp"

namespace mereo::io {

ColorImage colorize_depth(const DepthImage& depth) {
  std::vector<float> valid;
  valid.reserve(depth.pixels());
  for (std::size_t i = 0; i < depth.pixels(); ++i)
    if (std::isfinite(depth.data()[i]) && depth.data()[i] > 0) valid.push_back(depth.data()[i]);
  ColorImage out(depth.rows(), depth.cols(), 0);
  if (valid.empty()) return out;
  auto pct = [&](double q) {
    auto it = valid.begin() + std::ptrdiff_t(q * (valid.size() - 1));
    std::nth_element(valid.begin(), it, valid.end());
    return *it;
  };
  const float lo = pct(0.01), hi = std::max(pct(0.99), lo + 1e-3f);
  cv::Mat gray(depth.rows(), depth.cols(), CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < depth.rows(); ++v)
    for (int u = 0; u < depth.cols(); ++u) {
      const float z = depth(v, u);
      if (std::isfinite(z) && z > 0)
        gray.at<std::uint8_t>(v, u) = std::uint8_t(255 - std::clamp((z - lo) / (hi - lo), 0.f, 1.f) * 254);
    }
  cv::Mat bgr;
  cv::applyColorMap(gray, bgr, cv::COLORMAP_TURBO);
  for (int v = 0; v < depth.rows(); ++v)
    for (int u = 0; u < depth.cols(); ++u) {
      if (!gray.at<std::uint8_t>(v, u)) continue;
      const auto c = bgr.at<cv::Vec3b>(v, u);
      std::uint8_t* q = out.ptr(v, u);
      q[0] = c[2], q[1] = c[1], q[2] = c[0];
    }
  return out;
}

ColorImage colorize_normals(const NormalMap& normals) {
  ColorImage out(normals.rows(), normals.cols(), 0);
  for (std::size_t i = 0; i < normals.pixels(); ++i) {
    const float* n = normals.data() + 3 * i;
    if (!(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]))) continue;
    // The camera looks along +z, so normals facing it have n.z < 0: show -z as blue.
    const float c[3] = {n[0], n[1], -n[2]};
    for (int k = 0; k < 3; ++k)
      out.data()[3 * i + k] = std::uint8_t(std::clamp((c[k] + 1.f) * 127.5f, 0.f, 255.f));
  }
  return out;
}

ColorImage colorize_labels(const LabelImage& labels) {
  ColorImage out(labels.rows(), labels.cols(), 0);
  for (std::size_t i = 0; i < labels.pixels(); ++i) {
    const std::uint32_t l = labels.data()[i];
    if (!l) continue;
    // Golden-angle hues: neighbouring labels get distant colours.
    const float h = std::fmod(l * 137.508f, 360.f) / 60.f;
    const float x = 1.f - std::abs(std::fmod(h, 2.f) - 1.f);
    float r = 0, g = 0, b = 0;
    switch (int(h)) {
      case 0: r = 1, g = x; break;
      case 1: r = x, g = 1; break;
      case 2: g = 1, b = x; break;
      case 3: g = x, b = 1; break;
      case 4: r = x, b = 1; break;
      default: r = 1, b = x; break;
    }
    std::uint8_t* q = out.data() + 3 * i;
    q[0] = std::uint8_t(40 + 215 * r), q[1] = std::uint8_t(40 + 215 * g), q[2] = std::uint8_t(40 + 215 * b);
  }
  return out;
}

ColorImage hstack(const std::vector<ColorImage>& images, int gap) {
  int rows = 0, cols = 0;
  for (const auto& im : images) {
    rows = std::max(rows, im.rows());
    cols += im.cols() + gap;
  }
  ColorImage out(rows, std::max(0, cols - gap), 0);
  int x = 0;
  for (const auto& im : images) {
    for (int v = 0; v < im.rows(); ++v)
      std::copy(im.ptr(v, 0), im.ptr(v, 0) + 3 * im.cols(), out.ptr(v, x));
    x += im.cols() + gap;
  }
  return out;
}

namespace {

/// Pixel of a camera-frame point; nullopt behind the camera.
std::optional<cv::Point> project(const Intrinsics& K, const Eigen::Vector3d& x) {
  if (!(x.z() > 1e-3)) return std::nullopt;
  const Eigen::Vector2i px = K.pixel(x);
  return cv::Point(px.x(), px.y());
}

}  // namespace

ColorImage draw_objects(const ColorImage& color, const Intrinsics& K, const std::vector<DrawnObject>& objects) {
  if (color.empty()) throw InputError("draw_objects: the colour image is empty");
  if (!K.valid()) throw InputError("draw_objects: invalid intrinsics " + K.to_string());
  ColorImage out = color;
  cv::Mat img(out.rows(), out.cols(), CV_8UC3, out.data());
  static const cv::Scalar palette[] = {{255, 64, 64}, {64, 200, 64}, {64, 128, 255}, {255, 200, 0},
                                       {255, 0, 255}, {0, 220, 220}, {255, 128, 0}, {160, 96, 255}};
  const int thick = std::max(1, out.cols() / 320);
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const cv::Scalar c = objects[k].box ? cv::Scalar(170, 170, 170) : palette[k % 8];
    std::optional<cv::Point> anchor;
    if (const auto& b = objects[k].box) {
      cv::rectangle(img, cv::Point((*b)[0], (*b)[1]), cv::Point((*b)[2], (*b)[3]), c, thick);
      anchor = cv::Point(((*b)[0] + (*b)[2]) / 2, (*b)[1]);
    }
    for (const Segment& s : objects[k].parts) {
      const shapes::Outline outline = s.outline();  // the class's own, mereo/shapes/*.cpp
      for (const auto& line : outline.lines) {
        std::vector<cv::Point> l;
        for (const auto& x : line)
          if (auto p = project(K, x)) l.push_back(*p);
        if (line.size() == 2 && l.size() < 2) continue;  // a segment: both ends or nothing
        if (l.size() >= 2) cv::polylines(img, l, l.size() > 2, c, thick, cv::LINE_AA);
      }
      for (const auto& line : outline.pixels) {  // a 2-D primitive, as seen
        std::vector<cv::Point> l;
        for (const auto& x : line) l.emplace_back(int(std::lround(x.x())), int(std::lround(x.y())));
        if (l.size() >= 2) cv::polylines(img, l, false, c, thick, cv::LINE_AA);
        if (!anchor && !l.empty()) anchor = l.front();
      }
      if (outline.anchor && !anchor)
        if (auto p = project(K, *outline.anchor)) anchor = p;
    }
    if (anchor && !objects[k].label.empty()) {
      const double scale = 0.5;
      int base = 0;
      const cv::Size t = cv::getTextSize(objects[k].label, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base);
      const cv::Point at(std::clamp(anchor->x - t.width / 2, 0, std::max(0, out.cols() - t.width)),
                         std::clamp(anchor->y - 6, t.height + 2, out.rows() - 2));
      cv::rectangle(img, at + cv::Point(-2, base), at + cv::Point(t.width + 2, -t.height - 2), cv::Scalar(0, 0, 0),
                    cv::FILLED);
      cv::putText(img, objects[k].label, at, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
    }
  }
  return out;
}

void write_image(const std::string& path, const ColorImage& image) {
  if (image.empty()) throw InputError(path + ": the image to write is empty");
  const cv::Mat rgb(image.rows(), image.cols(), CV_8UC3, const_cast<std::uint8_t*>(image.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  bool ok = false;
  try {
    ok = cv::imwrite(path, bgr);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path + ": cannot write the image");
}

}  // namespace mereo::io
