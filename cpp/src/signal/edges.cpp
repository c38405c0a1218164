#include "mereo/signal/edges.hpp"

#include <algorithm>
#include <array>
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

/// Chains of the thin edge pixels (non-zero) of `edges`: walks from each end (a pixel with one
/// neighbour), then from what is left (closed outlines); each step goes on to the unvisited
/// 8-neighbour that turns least from the last step (a 4-neighbour on a tie: staircases keep
/// their corner pixels). A junction ends no walk: the straightest branch goes on, the others
/// are chains of their own.
std::vector<std::vector<cv::Point>> link_edges(const cv::Mat& edges, int min_length) {
  static const int dx[8] = {1, 0, -1, 0, 1, -1, -1, 1}, dy[8] = {0, 1, 0, -1, 1, 1, -1, -1};
  static const auto turns = [] {  // eighths of a full turn (0..4) from step a to step b
    std::array<std::array<int, 8>, 8> t{};
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double d = std::remainder(std::atan2(dy[b], dx[b]) - std::atan2(dy[a], dx[a]), 2 * M_PI);
        t[a][b] = int(std::lround(std::abs(d) / (M_PI / 4)));
      }
    return t;
  }();
  // the edge map with a border of one empty pixel, addressed by index: no bounds checks
  const int W = edges.cols, H = edges.rows, W2 = W + 2;
  cv::Mat padded;
  cv::copyMakeBorder(edges, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 0);
  std::uint8_t* m = padded.ptr<std::uint8_t>(0);
  int step[8];
  for (int k = 0; k < 8; ++k) step[k] = dy[k] * W2 + dx[k];
  constexpr std::uint8_t kEdge = 255, kVisited = 128;
  auto point = [&](int i) { return cv::Point(i % W2 - 1, i / W2 - 1); };
  auto walk = [&](int i, std::vector<cv::Point>& chain) {
    for (int last = -1;;) {  // the step that led here (-1: none)
      int best = -1, best_turn = 99;
      for (int k = 0; k < 8; ++k)
        if (m[i + step[k]] == kEdge) {
          const int turn = last < 0 ? 0 : turns[last][k];
          if (turn < best_turn) best = k, best_turn = turn;  // 4-neighbours first on a tie
        }
      if (best < 0 || best_turn > 2) return;  // an end, or a turn back of more than 90 degrees
      i += step[best];
      m[i] = kVisited;
      chain.push_back(point(i));
      last = best;
    }
  };
  std::vector<int> pixels;  // the edge pixels, in raster order, and which of them are ends
  std::vector<char> end;
  for (int y = 1; y <= H; ++y)
    for (int i = y * W2 + 1; i <= y * W2 + W; ++i)
      if (m[i]) {
        int n = 0;
        for (int k = 0; k < 8; ++k) n += m[i + step[k]] != 0;
        pixels.push_back(i);
        end.push_back(n == 1);
      }
  std::vector<std::vector<cv::Point>> out;
  for (int pass = 0; pass < 2; ++pass)  // from the ends first, then what is left (closed outlines)
    for (std::size_t e = 0; e < pixels.size(); ++e) {
      const int i = pixels[e];
      if (m[i] != kEdge || (pass == 0 && !end[e])) continue;
      m[i] = kVisited;
      std::vector<cv::Point> chain = {point(i)};
      walk(i, chain);
      if (pass == 1) {  // started inside an outline: the other way too, joined
        std::vector<cv::Point> back;
        walk(i, back);
        std::reverse(back.begin(), back.end());
        back.insert(back.end(), chain.begin(), chain.end());
        chain.swap(back);
      }
      if (int(chain.size()) >= min_length) out.push_back(std::move(chain));
    }
  // Canny leaves a second strand beside the first where an outline runs diagonally: a chain
  // whose pixels mostly touch a longer chain's is that longer chain again
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  std::fill(m, m + padded.total(), 0);  // now: the pixels of the chains kept
  std::vector<std::vector<cv::Point>> kept;
  for (auto& chain : out) {
    std::size_t touching = 0;
    for (const cv::Point& p : chain) {
      const int i = (p.y + 1) * W2 + p.x + 1;
      bool t = false;
      for (int k = 0; k < 8 && !t; ++k) t = m[i + step[k]] != 0;
      touching += t;
    }
    if (touching * 5 >= chain.size() * 4) continue;
    for (const cv::Point& p : chain) m[(p.y + 1) * W2 + p.x + 1] = 1;
    kept.push_back(std::move(chain));
  }
  return kept;
}

/// The median of |gx| + |gy| over every second pixel of every second row (a histogram: the
/// magnitudes are integers).
int median_gradient(const cv::Mat& gx, const cv::Mat& gy) {
  std::vector<int> histogram(2 * 1024 + 1, 0);
  int n = 0;
  for (int y = 0; y < gx.rows; y += 2) {
    const short *a = gx.ptr<short>(y), *b = gy.ptr<short>(y);
    for (int x = 0; x < gx.cols; x += 2, ++n)
      ++histogram[std::min<int>(2048, std::abs(a[x]) + std::abs(b[x]))];
  }
  for (int v = 0, below = 0;; ++v)
    if ((below += histogram[std::size_t(v)]) * 2 >= n) return v;
}

}  // namespace

std::vector<EdgeChain> detect_edges(const ColorImage& color, const EdgeOptions& o) {
  if (color.empty()) throw InputError("detect_edges: the colour image is empty");
  check_options(o);
  const cv::Mat rgb(color.rows(), color.cols(), CV_8UC3, const_cast<std::uint8_t*>(color.data()));
  cv::Mat grey;
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);

  // the gradient (the sub-pixel peak across the edge is found on it; Canny suppresses and links on it)
  cv::Mat smooth, gx, gy;
  if (o.subpixel || o.method == EdgeMethod::Canny || o.texture_factor > 0) {
    cv::GaussianBlur(grey, smooth, cv::Size(), o.sigma);
    cv::Sobel(smooth, gx, CV_16S, 1, 0);
    cv::Sobel(smooth, gy, CV_16S, 0, 1);
  }
  const double threshold =
      std::max(double(o.gradient_threshold), o.texture_factor > 0 ? o.texture_factor * median_gradient(gx, gy) : 0.0);
  std::vector<std::vector<cv::Point>> segments;
  if (o.method == EdgeMethod::Canny) {
    cv::Mat edges;
    cv::Canny(gx, gy, edges, threshold, 2.0 * threshold, false);
    segments = link_edges(edges, o.min_chain_px);
  } else {
    auto ed = cv::ximgproc::createEdgeDrawing();
    ed->params.GradientThresholdValue = int(std::lround(threshold));
    ed->params.AnchorThresholdValue = o.anchor_threshold;
    ed->params.Sigma = float(o.sigma);
    ed->params.MinPathLength = o.min_chain_px;
    ed->detectEdges(grey);
    segments = ed->getSegments();
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
