// The cone (mereo/shapes/cone.hpp), a class added to the shape table by one file pair: exact on
// exact samples, refitted from noisy points, and detected, written, drawn and matched through the
// table without anything else knowing it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "features/fit.hpp"
#include "mereo/features/primitives.hpp"
#include "mereo/io/visualize.hpp"
#include "mereo/knowledge/model_file.hpp"
#include "mereo/matching/interpret.hpp"
#include "mereo/matching/match.hpp"
#include "mereo/shapes/cone.hpp"

using namespace mereo;
using shapes::Cone;

namespace {

constexpr double kDeg = M_PI / 180;

/// A tapered cup's body: narrow end radius 3 cm, 8 degrees, 10 cm tall, its axis tilted.
Cone truth_cone() {
  Cone c;
  c.axis = Eigen::Vector3d(0.1, -1.0, 0.25).normalized();
  c.point = Eigen::Vector3d(0.03, 0.02, 0.75);
  c.angle = 8 * kDeg;
  c.height = 0.10;
  c.radius = 0.03 + std::tan(c.angle) * 0.05;
  return c;
}

/// A point of the cone at height t (from its point) and azimuth phi, and its outward normal.
std::pair<Eigen::Vector3d, Eigen::Vector3d> on_cone(const Cone& c, double t, double phi) {
  const Eigen::Vector3d a = c.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const Eigen::Vector3d u = std::cos(phi) * e1 + std::sin(phi) * e2;
  return {c.point + a * t + u * c.radius_at(t), (std::cos(c.angle) * u - std::sin(c.angle) * a).normalized()};
}

double axis_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) / kDeg;
}

}  // namespace

TEST(Cone, IsInTheShapeTable) {
  EXPECT_EQ(primitive_class("cone"), PrimitiveClass::of<Cone>());
  EXPECT_EQ(PrimitiveClass::of<Cone>().sample_size(), 3);
}

TEST(Cone, MinimalSetIsExactOnExactSamples) {
  const Cone c = truth_cone();
  Eigen::Vector3d P[3], N[3];
  const double tp[3][2] = {{-0.03, 0.2}, {0.01, 1.9}, {0.04, 4.0}};
  for (int k = 0; k < 3; ++k) std::tie(P[k], N[k]) = on_cone(c, tp[k][0], tp[k][1]);
  const auto fit = Cone::from_sample(P, N, {});
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->angle, c.angle, 1e-9);
  EXPECT_NEAR(axis_deg(fit->axis, c.axis), 0.0, 1e-6);
  EXPECT_GT(fit->axis.dot(c.axis), 0.0);  // pointing the way it widens
  EXPECT_NEAR((fit->apex() - c.apex()).norm(), 0.0, 1e-9);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(fit->signed_distance(P[k]), 0.0, 1e-9);
  // the distance is signed (outside > 0) and the normal is the surface's
  const auto [p, n] = on_cone(c, 0.02, 2.5);
  Eigen::Vector3d sn;
  EXPECT_NEAR(c.signed_distance(p + 0.004 * n, &sn), 0.004, 1e-9);
  EXPECT_NEAR(sn.dot(n), 1.0, 1e-9);
  EXPECT_NEAR(c.surface_distance(p - 0.004 * n), 0.0, 1e-12);  // inside the solid
  // a cylinder's samples (parallel tangent planes' normals all across one axis) give no cone
  Eigen::Vector3d Q[3], M[3];
  for (int k = 0; k < 3; ++k) {
    const double phi = tp[k][1];
    M[k] = Eigen::Vector3d(std::cos(phi), 0, std::sin(phi));
    Q[k] = Eigen::Vector3d(0, 0, 1) + 0.04 * M[k] + Eigen::Vector3d(0, tp[k][0], 0);
  }
  EXPECT_FALSE(Cone::from_sample(Q, M, {}));
}

TEST(Cone, RefitRecoversTheRadiiAndAxisFromNoisyPoints) {
  const Cone c = truth_cone();
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::uniform_real_distribution<double> T(-0.05, 0.05), F(-1.2, 1.2);  // the side facing a camera
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 800; ++i) {
    const auto [p, n] = on_cone(c, T(rng), F(rng));
    pts.push_back(p + n * noise(rng));
  }
  Cone start = c;
  start.point += Eigen::Vector3d(0.004, -0.003, 0.003);
  start.radius += 0.004, start.angle = 5 * kDeg;
  start.axis = (start.axis + Eigen::Vector3d(0.06, 0, 0.03)).normalized();
  Segment s = features::detail::refit_points(Segment(start), pts);
  features::detail::set_extent(s, pts);
  const Cone& fit = s.as<Cone>();
  EXPECT_LT(axis_deg(fit.axis, c.axis), 1.0);
  for (double t : {-0.05, 0.05}) {  // the radii at the true ends
    const Eigen::Vector3d end = c.point + c.axis * t;
    EXPECT_NEAR(fit.radius_at(fit.axis.normalized().dot(end - fit.point)), c.radius_at(t), 0.001) << "t " << t;
  }
  EXPECT_NEAR(fit.height, 0.10, 0.005);
  EXPECT_LT(s.residual, 0.0007);
}

TEST(Cone, DetectedWrittenDrawnAndMatchedThroughTheTable) {
  // a VGA frame (f = 525) of the cone's outside against a far wall, ray cast exactly, normals exact
  const Cone c = truth_cone();
  const Intrinsics K;
  Cloud cloud(480, 640, NAN);
  NormalMap normals(480, 640, NAN);
  const Eigen::Vector3d a = c.axis.normalized();
  const double k = std::tan(c.angle);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const Eigen::Vector3d d = Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1).normalized();
      const Eigen::Vector3d w = -c.point;  // the ray from the origin, relative to the cone's point
      const double da = d.dot(a), wa = w.dot(a);
      const Eigen::Vector3d dp = d - da * a, wp = w - wa * a;
      const double A = dp.squaredNorm() - k * k * da * da, B = dp.dot(wp) - k * da * (c.radius + k * wa),
                   C = wp.squaredNorm() - std::pow(c.radius + k * wa, 2);
      double t = 2.0;  // the wall
      Eigen::Vector3d n(0, 0, -1);
      const double disc = B * B - A * C;
      if (disc >= 0 && std::abs(A) > 1e-12)
        for (double r : {(-B - std::sqrt(disc)) / A, (-B + std::sqrt(disc)) / A}) {
          const double along = wa + r * da;
          if (r > 0 && r < t && std::abs(along) <= 0.5 * c.height && c.radius + k * along > 0) {
            t = r;
            const Eigen::Vector3d q = wp + r * dp;
            n = (q.normalized() - k * a).normalized();
          }
        }
      const Eigen::Vector3d x = t * d;
      if (n.dot(d) > 0) n = -n;  // towards the camera
      for (int j = 0; j < 3; ++j) cloud(v, u, j) = float(x(j)), normals(v, u, j) = float(n(j));
    }
  features::DetectOptions o;
  o.classes = {PrimitiveClass::of<shapes::Plane>(), PrimitiveClass::of<Cone>()};
  const auto segs = features::detect_primitives(cloud, normals, o);
  const Segment* found = nullptr;
  for (const auto& s : segs)
    if (s.is<Cone>() && (!found || s.inliers > found->inliers)) found = &s;
  ASSERT_NE(found, nullptr);
  const Cone& fit = found->as<Cone>();
  EXPECT_LT(axis_deg(fit.axis, c.axis), 2.0);
  for (double t : {-0.05, 0.05}) {
    const Eigen::Vector3d end = c.point + c.axis * t;
    const double r = fit.radius_at(fit.axis.normalized().dot(end - fit.point));
    std::printf("ray-cast cone: radius at %+.2f m: %.2f mm off; axis %.3f deg off; %zu inliers\n", t,
                1000 * (r - c.radius_at(t)), axis_deg(fit.axis, c.axis), found->inliers);
    EXPECT_NEAR(r, c.radius_at(t), 0.002) << "t " << t;
  }
  // JSON: the class's own fields
  const std::string json = matching::result_json(Frame{}, segs, {}, nullptr, {});
  EXPECT_NE(json.find("\"class\":\"cone\""), std::string::npos);
  EXPECT_NE(json.find("\"half_angle_deg\""), std::string::npos);
  EXPECT_NE(json.find("\"radius_wide\""), std::string::npos);
  // drawing: its outline lands on the image
  const ColorImage black(480, 640, 0);
  const ColorImage drawn = io::draw_objects(black, K, {{"cup", {*found}}});
  int lit = 0;
  for (std::size_t i = 0; i < drawn.size(); ++i) lit += drawn.data()[i] != 0;
  EXPECT_GT(lit, 300);
  // matching: a model whose body is a cone, judged by the cone's attributes
  knowledge::KnowledgeBase kb;
  knowledge::parse_models(kb, R"(
concepts:
  - name: tapered_cup
    parts:
      - {role: body, class: cone}
    attributes:
      - {part: body, attribute: half_angle_deg, range: [3, 12], margin: 1}
      - {part: body, attribute: radius_narrow, range: [0.02, 0.04], margin: 0.005}
)");
  const auto hyps = matching::match(kb.resolve("tapered_cup"), segs);
  ASSERT_FALSE(hyps.empty());
  EXPECT_TRUE(segs[std::size_t(hyps.front().assignment[0])].is<Cone>());
  EXPECT_GT(hyps.front().score, 0.9);
}
