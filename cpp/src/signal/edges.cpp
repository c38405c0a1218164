#include "mereo/signal/edges.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>

#include "mereo/core/error.hpp"

namespace mereo::signal {

namespace {

/// The offset (-0.5 .. 0.5) of the peak of the parabola through (-1, a), (0, b), (1, c).
float parabola_peak(float a, float b, float c) {
  const float den = a - 2 * b + c;
  return den < 0 ? std::clamp(0.5f * (a - c) / den, -0.5f, 0.5f) : 0.f;
}

}  // namespace

std::vector<EdgeChain> detect_edges(const ColorImage& color, const EdgeOptions& o) {
  if (color.empty()) throw InputError("detect_edges: the colour image is empty");
  check_options(o);
  const cv::Mat rgb(color.rows(), color.cols(), CV_8UC3, const_cast<std::uint8_t*>(color.data()));
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);

  auto ed = cv::ximgproc::createEdgeDrawing();
  ed->params.GradientThresholdValue = o.gradient_threshold;
  ed->params.AnchorThresholdValue = o.anchor_threshold;
  ed->params.Sigma = float(o.sigma);
  ed->params.MinPathLength = o.min_chain_px;
  ed->detectEdges(grey);
  const std::vector<std::vector<cv::Point>> segments = ed->getSegments();

  // the gradient magnitude ED walked on, for the sub-pixel peak across the edge
  cv::Mat gx, gy;
  if (o.subpixel) {
    cv::Mat smooth;
    cv::GaussianBlur(grey, smooth, cv::Size(), o.sigma);
    cv::Sobel(smooth, gx, CV_16S, 1, 0);
    cv::Sobel(smooth, gy, CV_16S, 0, 1);
  }
  const int W = grey.cols, H = grey.rows;
  auto mag = [&](int x, int y) {
    x = std::clamp(x, 0, W - 1), y = std::clamp(y, 0, H - 1);
    return float(std::abs(gx.at<short>(y, x)) + std::abs(gy.at<short>(y, x)));
  };

  std::vector<EdgeChain> out;
  out.reserve(segments.size());
  for (const auto& s : segments) {
    if (int(s.size()) < o.min_chain_px) continue;
    EdgeChain c;
    c.points.reserve(s.size());
    for (const cv::Point& p : s) {
      Eigen::Vector2f q(float(p.x), float(p.y));
      if (o.subpixel) {
        const float dx = gx.at<short>(p.y, p.x), dy = gy.at<short>(p.y, p.x);
        if (std::abs(dx) >= std::abs(dy))  // the edge runs across x: its peak moves along x
          q.x() += parabola_peak(mag(p.x - 1, p.y), mag(p.x, p.y), mag(p.x + 1, p.y));
        else
          q.y() += parabola_peak(mag(p.x, p.y - 1), mag(p.x, p.y), mag(p.x, p.y + 1));
      }
      c.points.push_back(q);
    }
    out.push_back(std::move(c));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const EdgeChain& a, const EdgeChain& b) { return a.points.size() > b.points.size(); });
  return out;
}

}  // namespace mereo::signal
