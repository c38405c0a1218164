// Standalone sanity check for the benchmark's reference detectors (anchors.hpp):
// builds a synthetic scene with one plane, cylinder, sphere and torus (exact
// normals, 1 mm Gaussian noise on positions), runs both adapters and reports
// what they found against the ground truth. Not part of the build; compile by
// hand, e.g. (one line)
//   g++ -O2 -std=c++17 -I/usr/include/eigen3 -I/usr/include/pcl-1.13
//     tests/bench/anchors/*.cpp -o /tmp/anchors/check -lpcl_segmentation
//     -lpcl_sample_consensus -lpcl_common -lgmp -lmpfr
#include "anchors.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

using mereo::bench::AnchorOptions;
using mereo::bench::AnchorShape;

namespace {

double now_ms() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

struct Scene {
  std::vector<Eigen::Vector3f> points, normals;
  std::vector<int> label;  // ground-truth shape index per point
  std::vector<AnchorShape> truth;
};

AnchorShape shape(const char* cls, const Eigen::Vector3d& point, const Eigen::Vector3d& axis,
                  double radius = 0, double minor_radius = 0) {
  AnchorShape a;
  a.cls = cls;
  a.point = point;
  a.axis = axis;
  a.radius = radius;
  a.minor_radius = minor_radius;
  return a;
}

Scene make_scene(unsigned seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.001);
  auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, int lab) {
    const Eigen::Vector3d q = p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    s.points.push_back(q.cast<float>());
    s.normals.push_back(n.normalized().cast<float>());
    s.label.push_back(lab);
  };
  const double kPi = M_PI;

  // 0: plane z = 1 on [-0.3, 0.3] x [-0.3, 0.3].
  const AnchorShape plane = shape("plane", {0, 0, 1}, {0, 0, 1});
  for (int i = 0; i < 5000; ++i)
    add({-0.3 + 0.6 * uni(rng), -0.3 + 0.6 * uni(rng), 1.0}, {0, 0, 1}, 0);

  // 1: cylinder r = 0.04, axis along y through (0.45, *, 1.1), length 0.2.
  const AnchorShape cyl = shape("cylinder", {0.45, 0, 1.1}, {0, 1, 0}, 0.04);
  for (int i = 0; i < 4000; ++i) {
    const double t = 2 * kPi * uni(rng), y = -0.1 + 0.2 * uni(rng);
    const Eigen::Vector3d n(std::cos(t), 0, std::sin(t));
    add(cyl.point + Eigen::Vector3d(0, y, 0) + cyl.radius * n, n, 1);
  }

  // 2: sphere r = 0.05 centred at (-0.45, 0, 1.1).
  const AnchorShape sph = shape("sphere", {-0.45, 0, 1.1}, {0, 0, 1}, 0.05);
  for (int i = 0; i < 4000; ++i) {
    Eigen::Vector3d n(noise(rng), noise(rng), noise(rng));
    n.normalize();
    add(sph.point + sph.radius * n, n, 2);
  }

  // 3: torus R = 0.04, r = 0.006 centred at (0, 0.45, 1.1), ring plane normal z.
  const AnchorShape tor = shape("torus", {0, 0.45, 1.1}, {0, 0, 1}, 0.04, 0.006);
  for (int i = 0; i < 3000;) {
    const double u = 2 * kPi * uni(rng), v = 2 * kPi * uni(rng);
    // Area element is proportional to R + r cos v: rejection-sample it.
    if (uni(rng) * (tor.radius + tor.minor_radius) > tor.radius + tor.minor_radius * std::cos(v))
      continue;
    const Eigen::Vector3d radial(std::cos(u), std::sin(u), 0);
    const Eigen::Vector3d n = std::cos(v) * radial + std::sin(v) * Eigen::Vector3d::UnitZ();
    add(tor.point + tor.radius * radial + tor.minor_radius * n, n, 3);
    ++i;
  }
  s.truth = {plane, cyl, sph, tor};
  return s;
}

// Distance from point p to the line through c with unit direction d.
double line_dist(const Eigen::Vector3d& p, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (p - c - (p - c).dot(d) * d).norm();
}

void report(const char* name, const std::vector<AnchorShape>& found, const Scene& s, double ms) {
  std::printf("== %s: %zu shapes in %.1f ms\n", name, found.size(), ms);
  for (const auto& a : found) {
    // Majority ground-truth label among the inliers.
    int votes[4] = {0, 0, 0, 0};
    for (int i : a.indices) ++votes[s.label[i]];
    int best = 0;
    for (int k = 1; k < 4; ++k)
      if (votes[k] > votes[best]) best = k;
    const AnchorShape& t = s.truth[best];
    const double purity = a.indices.empty() ? 0 : double(votes[best]) / a.indices.size();
    const double ang = std::acos(std::min(1.0, std::abs(a.axis.dot(t.axis)))) * 180 / M_PI;
    std::printf("  %-8s n=%5zu  (gt %-8s purity %.3f)  ", a.cls.c_str(), a.indices.size(),
                t.cls.c_str(), purity);
    bool ok = a.cls == t.cls;
    if (a.cls == "plane") {
      const double off = std::abs(a.axis.dot(t.point - a.point));
      std::printf("normal err %.2f deg, offset err %.2f mm", ang, 1e3 * off);
      ok = ok && ang < 2 && off < 0.002;
    } else if (a.cls == "cylinder") {
      const double dr = std::abs(a.radius - t.radius), da = line_dist(t.point, a.point, a.axis);
      std::printf("r=%.4f (err %.2f mm), axis err %.2f deg, axis offset %.2f mm", a.radius,
                  1e3 * dr, ang, 1e3 * da);
      ok = ok && dr < 0.002 && ang < 3 && da < 0.003;
    } else if (a.cls == "sphere") {
      const double dr = std::abs(a.radius - t.radius), dc = (a.point - t.point).norm();
      std::printf("r=%.4f (err %.2f mm), centre err %.2f mm", a.radius, 1e3 * dr, 1e3 * dc);
      ok = ok && dr < 0.002 && dc < 0.003;
    } else if (a.cls == "torus") {
      const double dR = std::abs(a.radius - t.radius);
      const double dr = std::abs(a.minor_radius - t.minor_radius);
      const double dc = (a.point - t.point).norm();
      std::printf("R=%.4f r=%.4f (err %.2f / %.2f mm), centre err %.2f mm, axis err %.2f deg",
                  a.radius, a.minor_radius, 1e3 * dR, 1e3 * dr, 1e3 * dc, ang);
      ok = ok && dR < 0.002 && dr < 0.002 && dc < 0.003 && ang < 5;
    }
    std::printf("  %s\n", ok ? "OK" : "MISMATCH");
  }
}

}  // namespace

int main() {
  const Scene s = make_scene(1);
  std::printf("scene: %zu points\n", s.points.size());
  AnchorOptions o;

  double t0 = now_ms();
  const auto cg = mereo::bench::cgal_efficient_ransac(s.points, s.normals, o, 0);
  report("CGAL Efficient_RANSAC", cg, s, now_ms() - t0);

  // Determinism: same seed, same result.
  const auto cg2 = mereo::bench::cgal_efficient_ransac(s.points, s.normals, o, 0);
  bool same = cg.size() == cg2.size();
  for (size_t i = 0; same && i < cg.size(); ++i) same = cg[i].indices == cg2[i].indices;
  std::printf("  repeat with same seed identical: %s\n", same ? "yes" : "no");
  t0 = now_ms();
  const auto cg3 = mereo::bench::cgal_efficient_ransac(s.points, s.normals, o, 7);
  report("CGAL Efficient_RANSAC, seed 7", cg3, s, now_ms() - t0);

  t0 = now_ms();
  const auto pc = mereo::bench::pcl_sac_cylinders(s.points, s.normals, o);
  report("PCL SACSegmentationFromNormals", pc, s, now_ms() - t0);
  return 0;
}
