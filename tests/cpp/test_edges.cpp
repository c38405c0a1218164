// Tests of the edge modality's signal and feature layers (signal/edges.hpp, features/edges.hpp):
// lines and elliptical arcs against shapes drawn with known parameters, the outlines of rendered
// objects against the renderer's label image, and lifted rims against the rendered mugs.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "../bench/eval_edges.hpp"
#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"
#include "mereo/features/edges.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/match.hpp"
#include "mereo/signal/edges.hpp"
#include "mereo/synthetic/scene.hpp"

namespace {

using mereo::ColorImage;
using mereo::Segment;
namespace sh = mereo::shapes;

/// A 640 x 480 grey-on-white drawing (noise of 4 grey levels) of what `draw` paints. The noise is
/// the same in every call (OpenCV's global generator would give each test the draws the tests
/// before it left: the Edge Drawing chains lost a side of the short cylinder under some of them).
template <class Draw>
ColorImage drawing(Draw draw) {
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(200, 200, 200));
  draw(img);
  cv::Mat noise(img.size(), CV_16SC3);
  cv::RNG rng;  // OpenCV's default state
  rng.fill(noise, cv::RNG::NORMAL, 0, 4);
  cv::Mat out;
  img.convertTo(out, CV_16SC3);
  out += noise;
  out.convertTo(img, CV_8UC3);
  ColorImage c(480, 640);
  std::copy(img.data, img.data + img.total() * 3, c.data());
  return c;
}

std::vector<Segment> primitives(const ColorImage& c, mereo::signal::EdgeMethod method = mereo::signal::EdgeMethod::Canny) {
  mereo::signal::EdgeOptions o;
  o.method = method;
  return mereo::features::fit_edge_primitives(mereo::signal::detect_edges(c, o), c, nullptr);
}

/// Both sources of edge chains (signal/edges.hpp), for the tests of drawn shapes.
class EdgesOfDrawings : public ::testing::TestWithParam<mereo::signal::EdgeMethod> {};
INSTANTIATE_TEST_SUITE_P(Chains, EdgesOfDrawings,
                         ::testing::Values(mereo::signal::EdgeMethod::Canny, mereo::signal::EdgeMethod::EdgeDrawing),
                         [](const auto& info) {
                           return info.param == mereo::signal::EdgeMethod::Canny ? "Canny" : "EdgeDrawing";
                         });

/// The arc whose ellipse centre lies nearest `centre`; null when there is none.
const sh::Arc* arc_near(const std::vector<Segment>& s, const Eigen::Vector2d& centre) {
  const sh::Arc* best = nullptr;
  for (const auto& x : s)
    if (const auto* a = x.get_if<sh::Arc>())
      if (!best || (a->center_px - centre).norm() < (best->center_px - centre).norm()) best = a;
  return best;
}

/// Distance of point q to the segment a-b.
double to_segment(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp(d.dot(q - a) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d - q).norm();
}

TEST_P(EdgesOfDrawings, AnEllipseAndARectangleAreAnArcAndFourLines) {
  const ColorImage c = drawing([](cv::Mat& img) {
    cv::ellipse(img, cv::Point(420, 250), cv::Size(110, 60), 25, 0, 360, cv::Scalar(60, 90, 160), cv::FILLED, cv::LINE_AA);
    cv::rectangle(img, cv::Point(60, 80), cv::Point(220, 300), cv::Scalar(40, 40, 40), cv::FILLED);
  });
  const auto s = primitives(c, GetParam());
  const sh::Arc* a = arc_near(s, {420, 250});
  ASSERT_NE(a, nullptr);
  EXPECT_NEAR(a->center_px.x(), 420, 1.0);
  EXPECT_NEAR(a->center_px.y(), 250, 1.0);
  EXPECT_NEAR(a->axes_px.x(), 110, 1.5);  // the edge lies half a pixel outside cv::ellipse's axes at most
  EXPECT_NEAR(a->axes_px.y(), 60, 1.5);
  EXPECT_NEAR(a->angle_deg, 25, 2.0);
  EXPECT_GT(a->span_deg(), 300);
  EXPECT_FALSE(a->lifted);
  // inside the ellipse is its colour, outside the background's
  EXPECT_NEAR(a->sides.a.x(), 60 / 255.0, 0.05);
  EXPECT_NEAR(a->sides.b.x(), 200 / 255.0, 0.05);

  // each side of the rectangle is one line along it, covering most of it
  const Eigen::Vector2d corner[4] = {{60, 80}, {220, 80}, {220, 300}, {60, 300}};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d p = corner[k], q = corner[(k + 1) % 4];
    double covered = 0;
    for (const auto& x : s)
      if (const auto* l = x.get_if<sh::Line>())
        if (to_segment(l->start_px, p, q) < 1.5 && to_segment(l->end_px, p, q) < 1.5) covered += l->length_px();
    EXPECT_GT(covered, 0.8 * (q - p).norm()) << "side " << k;
  }
  // and nothing else is there: no line off the rectangle, no other arc of any size
  for (const auto& x : s)
    if (const auto* l = x.get_if<sh::Line>()) {
      double off = 1e9;
      for (int k = 0; k < 4; ++k) off = std::min(off, to_segment(l->start_px, corner[k], corner[(k + 1) % 4]));
      EXPECT_LT(off, 2.0) << "a line from " << l->start_px.transpose() << " to " << l->end_px.transpose();
    } else if (const auto* b = x.get_if<sh::Arc>()) {
      EXPECT_EQ(b, a) << "an arc about " << b->center_px.transpose();
    }
}

TEST_P(EdgesOfDrawings, APartlyHiddenDiscIsAnArcOfWhatIsSeen) {
  // a disc of radius 70 whose right half a box hides: its edge is a half circle
  const ColorImage c = drawing([](cv::Mat& img) {
    cv::circle(img, cv::Point(300, 240), 70, cv::Scalar(150, 40, 40), cv::FILLED, cv::LINE_AA);
    cv::rectangle(img, cv::Point(300, 100), cv::Point(500, 380), cv::Scalar(90, 160, 90), cv::FILLED);
  });
  const auto s = primitives(c, GetParam());
  const sh::Arc* a = arc_near(s, {300, 240});
  ASSERT_NE(a, nullptr);
  EXPECT_NEAR(a->center_px.x(), 300, 1.5);
  EXPECT_NEAR(a->center_px.y(), 240, 1.5);
  // a half circle holds its ellipse less firmly than a whole one, and its ends meet the box's edge
  EXPECT_NEAR(a->axes_px.x(), 70.5, 2.0);
  EXPECT_NEAR(a->axes_px.y(), 70.5, 2.0);
  EXPECT_NEAR(a->span_deg(), 180, 12);
  // the arc's middle is the disc's leftmost point
  const Eigen::Vector2d mid = a->at((a->start_deg + a->end_deg) / 2);
  EXPECT_NEAR(mid.x(), 230, 3);
  EXPECT_NEAR(mid.y(), 240, 3);
}

TEST(Edges, ADrawnCylinderIsAnEdgeCylinderAndAnUnrelatedCircleBesideTwoLinesIsNone) {
  // a cylinder's outline: its two sides (x = 250 and 350, y 200-330), its top face's ellipse (a
  // lighter colour: the rim is an edge all round) and its bottom's near half
  const ColorImage cylinder = drawing([](cv::Mat& img) {
    cv::ellipse(img, cv::Point(300, 330), cv::Size(50, 16), 0, 0, 180, cv::Scalar(60, 60, 140), cv::FILLED, cv::LINE_AA);
    cv::rectangle(img, cv::Point(250, 200), cv::Point(350, 330), cv::Scalar(60, 60, 140), cv::FILLED);
    cv::ellipse(img, cv::Point(300, 200), cv::Size(50, 16), 0, 0, 360, cv::Scalar(120, 120, 230), cv::FILLED, cv::LINE_AA);
  });
  // the same lines and an ellipse of the same size, apart: no cylinder
  const ColorImage apart = drawing([](cv::Mat& img) {
    cv::rectangle(img, cv::Point(250, 200), cv::Point(350, 330), cv::Scalar(60, 60, 140), cv::FILLED);
    cv::ellipse(img, cv::Point(520, 100), cv::Size(50, 16), 0, 0, 360, cv::Scalar(120, 120, 230), cv::FILLED, cv::LINE_AA);
  });
  const auto& kb = mereo::knowledge::builtin_models();
  // the best hypothesis of a modality: the sides (rim, left, right) or the base (rim, base)
  auto best = [&](const ColorImage& c, std::vector<Segment>& s, const std::string& modality = "sides") {
    s = primitives(c);
    for (const auto& h : mereo::matching::recognize(kb, {"edge_cylinder"}, s).hypotheses)
      if (h.modality == modality) return h;
    return mereo::matching::Hypothesis{};
  };
  std::vector<Segment> s;
  const auto h = best(cylinder, s);
  ASSERT_GT(h.score, 0.5);
  const auto& rim = s[std::size_t(h.assignment[0])].as<sh::Arc>();
  EXPECT_NEAR(rim.center_px.x(), 300, 2);
  EXPECT_NEAR(rim.axes_px.x(), 50, 2);
  const auto& a = s[std::size_t(h.assignment[1])].as<sh::Line>();
  const auto& b = s[std::size_t(h.assignment[2])].as<sh::Line>();
  EXPECT_NEAR(std::abs(a.start_px.x() - b.start_px.x()), 100, 3);  // the two sides, not one twice
  EXPECT_NEAR(std::min(a.start_px.x(), b.start_px.x()), 250, 2);
  EXPECT_LT(best(apart, s).score, 0.5);
  EXPECT_LT(best(apart, s, "base").score, 0.5);

  // the base under the rim: the same cylinder by its rim and the near half of its bottom's ellipse
  const auto hb = best(cylinder, s, "base");
  ASSERT_GT(hb.score, 0.5);
  EXPECT_NEAR(s[std::size_t(hb.assignment[0])].as<sh::Arc>().center_px.y(), 200, 2);
  EXPECT_NEAR(s[std::size_t(hb.assignment[1])].as<sh::Arc>().center_px.y(), 330, 3);
  // a plate's rim and its well (concentric: nothing below the rim) are no cylinder
  const ColorImage plate = drawing([](cv::Mat& img) {
    cv::ellipse(img, cv::Point(300, 200), cv::Size(80, 30), 0, 0, 360, cv::Scalar(120, 120, 230), cv::FILLED, cv::LINE_AA);
    cv::ellipse(img, cv::Point(300, 202), cv::Size(60, 22), 0, 0, 360, cv::Scalar(90, 90, 200), cv::FILLED, cv::LINE_AA);
  });
  EXPECT_LT(best(plate, s, "base").score, 0.5);
}

TEST(Edges, AShortCylindersSidesAreLinesNotPartOfItsBasesArc) {
  // a can seen from above (rendered 9516's, drawn): sides of 30 px at x = 260 and 340 running
  // tangentially into the near half of its base's ellipse (axes 40 x 34). An ellipse grown from
  // a side into the base's arc held both within tolerance (one arc of axes 32 x 24 and no left
  // side); a straight run longer than any chord of the ellipse within the split tolerance is a
  // line, so both sides are
  const ColorImage can = drawing([](cv::Mat& img) {
    cv::ellipse(img, cv::Point(300, 230), cv::Size(40, 34), 0, 0, 180, cv::Scalar(60, 140, 60), cv::FILLED, cv::LINE_AA);
    cv::rectangle(img, cv::Point(260, 200), cv::Point(340, 230), cv::Scalar(60, 140, 60), cv::FILLED);
    cv::ellipse(img, cv::Point(300, 200), cv::Size(40, 34), 0, 0, 360, cv::Scalar(130, 230, 130), cv::FILLED, cv::LINE_AA);
  });
  for (auto method : {mereo::signal::EdgeMethod::Canny, mereo::signal::EdgeMethod::EdgeDrawing}) {
    const auto s = primitives(can, method);
    auto side = [&](double x) {
      return std::any_of(s.begin(), s.end(), [&](const Segment& g) {
        const auto* l = g.get_if<sh::Line>();
        return l && std::abs(l->start_px.x() - x) < 3 && std::abs(l->end_px.x() - x) < 3 && l->length_px() > 20;
      });
    };
    EXPECT_TRUE(side(260)) << "the left side, chains " << int(method);
    EXPECT_TRUE(side(340)) << "the right side, chains " << int(method);
  }
}

/// What the edge primitives' pixels reach of the outlines of a rendered frame's objects (not of
/// the table, floor or walls), within 2 pixels.
double outline_recall(const mereo::synthetic::SyntheticFrame& f, const std::vector<Segment>& s, std::size_t* count) {
  const auto truth = mereo::bench::outline_pixels(f.truth.objects, f.frame.color, [&](std::uint32_t l) {
    const auto* o = f.truth.object(l);
    return o && o->model != "table" && o->model != "floor" && o->model != "wall";
  });
  *count = truth.size();
  return mereo::bench::outline_recall(truth, mereo::bench::segment_mask(s, f.frame.rows(), f.frame.cols()), 2);
}

TEST(Edges, LinesAndArcsTraceTheOutlinesOfRenderedObjects) {
  // (the colour image is the same under both depth models: the handle shapes vary instead)
  for (auto handles : {mereo::synthetic::HandleShapes::Torus, mereo::synthetic::HandleShapes::Varied}) {
    mereo::synthetic::SceneOptions so;
    so.handle_shapes = handles;
    double sum = 0;
    int n = 0;
    for (std::uint64_t seed : {9101u, 9102u, 9103u, 9104u}) {
      const auto f = mereo::synthetic::render(seed, so);
      std::size_t count = 0;
      const double r = outline_recall(f, mereo::features::detect_edge_primitives(f.frame), &count);
      ASSERT_GT(count, 500u);
      std::cout << "seed " << seed << ": " << count << " outline pixels, recall " << r << "\n";
      sum += r, ++n;
    }
    EXPECT_GT(sum / n, 0.75);
  }
}

TEST(Edges, TheLiftedRimOfARenderedMugHasTheMugsRadius) {
  // the arc on a mug's rim (most of its pixels within 2 pixels of the rim's), lifted to 3-D, is a
  // circle of the body's radius about its axis (the rim is 3-5 mm wide: its inner edge counts too)
  int checked = 0;
  for (std::uint64_t seed = 9110; seed < 9120; ++seed) {
    const auto f = mereo::synthetic::render(seed);
    const auto s = mereo::features::detect_edge_primitives(f.frame);
    for (const auto& o : f.truth.objects_truth) {
      const auto* rim = o.part("rim");
      if (o.model != "mug" || !rim || rim->visible_pixels < 150) continue;
      cv::Mat on(f.frame.rows(), f.frame.cols(), CV_8U, cv::Scalar(0));
      for (std::size_t i = 0; i < on.total(); ++i) on.data[i] = f.truth.parts.data()[i] == rim->label;
      cv::dilate(on, on, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
      const sh::Arc* best = nullptr;
      std::size_t most = 0;
      for (const auto& x : s)
        if (const auto* a = x.get_if<sh::Arc>(); a && a->lifted && x.pixels.size() >= 30) {
          std::size_t n = 0;
          for (int i : x.pixels) n += on.data[i];
          if (n >= 0.6 * x.pixels.size() && n > most) best = a, most = n;
        }
      if (!best) continue;
      ++checked;
      const double R = rim->camera.radius;
      EXPECT_NEAR(best->radius, R - 0.002, 0.15 * R) << "seed " << seed;
      EXPECT_GT(std::abs(best->normal.dot(rim->camera.axis.normalized())), std::cos(20 * M_PI / 180)) << "seed " << seed;
      EXPECT_LT((best->center - rim->camera.point).norm(), 0.3 * R) << "seed " << seed;
    }
  }
  std::cout << checked << " rims checked\n";
  EXPECT_GE(checked, 4);
}

TEST(Edges, ATexturedBackgroundRaisesTheThresholdAndKeepsTheOutline) {
  // a dark disc on a wood-like grain (stripes of +-14 grey levels that wander, the noise on top):
  // the fixed threshold takes the grain's edges, the raised one keeps the disc's outline alone
  auto grain = [](cv::Mat& img) {
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {
        const double g = 150 + 14 * std::sin(0.45 * x + 4 * std::sin(0.03 * y) + 2 * std::sin(0.011 * x * y / 40.0));
        img.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(g), cv::saturate_cast<uchar>(g * 0.8),
                                            cv::saturate_cast<uchar>(g * 0.6));
      }
    cv::circle(img, cv::Point(320, 240), 80, cv::Scalar(40, 30, 150), cv::FILLED, cv::LINE_AA);
  };
  const ColorImage textured = drawing(grain);
  auto off_disc = [](const std::vector<mereo::signal::EdgeChain>& chains) {  // edge points off the disc's outline
    std::size_t n = 0;
    for (const auto& c : chains)
      for (const auto& p : c.points) n += std::abs((p - Eigen::Vector2f(320, 240)).norm() - 80.5f) > 3;
    return n;
  };
  mereo::signal::EdgeOptions fixed;
  fixed.texture_factor = 0;
  const auto raised = mereo::signal::detect_edges(textured), all = mereo::signal::detect_edges(textured, fixed);
  EXPECT_GT(off_disc(all), 2000u);
  EXPECT_LT(off_disc(raised), off_disc(all) / 10);
  const auto s = mereo::features::fit_edge_primitives(raised, textured, nullptr);
  const sh::Arc* a = arc_near(s, {320, 240});
  ASSERT_NE(a, nullptr);
  EXPECT_NEAR(a->center_px.x(), 320, 1.0);
  EXPECT_NEAR(a->axes_px.x(), 80.5, 1.5);
  EXPECT_GT(a->span_deg(), 300);

  // on a plain background the median gradient is the noise's: the threshold stays where it was
  const ColorImage plain = drawing([](cv::Mat& img) {
    cv::circle(img, cv::Point(320, 240), 80, cv::Scalar(40, 30, 150), cv::FILLED, cv::LINE_AA);
  });
  const auto p1 = mereo::signal::detect_edges(plain), p0 = mereo::signal::detect_edges(plain, fixed);
  ASSERT_EQ(p1.size(), p0.size());
  for (std::size_t k = 0; k < p1.size(); ++k) EXPECT_EQ(p1[k].points, p0[k].points);
}

TEST(Edges, BadInputIsAClearError) {
  EXPECT_THROW(mereo::signal::detect_edges(ColorImage()), mereo::InputError);
  mereo::signal::EdgeOptions o;
  o.sigma = 0;
  EXPECT_THROW(mereo::signal::detect_edges(ColorImage(10, 10), o), mereo::InputError);
  const ColorImage c(48, 64, 128);
  const mereo::Cloud wrong(10, 10);
  EXPECT_THROW(mereo::features::fit_edge_primitives({}, c, &wrong), mereo::InputError);
  mereo::Frame f;
  f.depth = mereo::DepthImage(48, 64);
  EXPECT_THROW(mereo::features::detect_edge_primitives(f), mereo::InputError);
  // a blank image has no edges: an empty result, no error
  EXPECT_TRUE(primitives(c).empty());
}

}  // namespace
