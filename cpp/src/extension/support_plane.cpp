// The support plane (the table) and the region of interest above it.
#include "mereo/extension/support_plane.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mereo/core/error.hpp"

namespace mereo::extension {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Inlier tolerance at depth z: epsilon grows with z^2 (Kinect axial noise), never below
/// its value at 0.7 m.
inline double tolerance(double epsilon, double z) { return epsilon * std::max(z * z, 0.5); }

struct Sample {
  Eigen::Vector3f p, n;
  bool central;
};

/// The pixels (1) within the inlier distance of the plane (n, d) and, given normals, whose normal
/// is within acos(cos_dev) of n, on every `stride`-th pixel of every `stride`-th row.
cv::Mat near_plane(const Cloud& cloud, const NormalMap* normals, const Eigen::Vector3d& n, double d, double eps,
                   double cos_dev, int stride) {
  const int H = (cloud.rows() + stride - 1) / stride, W = (cloud.cols() + stride - 1) / stride;
  cv::Mat mask(H, W, CV_8U, cv::Scalar(0));
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      std::uint8_t* m = mask.ptr<std::uint8_t>(v);
      for (int u = 0; u < W; ++u) {
        const float* p = cloud.ptr(stride * v, stride * u);
        if (!valid_point(p)) continue;
        const double dist = std::abs(n.x() * p[0] + n.y() * p[1] + n.z() * p[2] + d);
        if (dist > tolerance(eps, p[2])) continue;
        if (normals) {
          const float* q = normals->ptr(stride * v, stride * u);
          if (!std::isfinite(q[0]) || std::abs(n.x() * q[0] + n.y() * q[1] + n.z() * q[2]) < cos_dev) continue;
        }
        m[u] = 1;
      }
    }
  });
  return mask;
}

/// 255 where `labels` holds a label that `keep` marks, 0 elsewhere.
cv::Mat kept_labels(const cv::Mat& labels, const std::vector<std::uint8_t>& keep) {
  cv::Mat out(labels.rows, labels.cols, CV_8U, cv::Scalar(0));
  for (int v = 0; v < labels.rows; ++v) {
    const int* l = labels.ptr<int>(v);
    std::uint8_t* o = out.ptr<std::uint8_t>(v);
    for (int u = 0; u < labels.cols; ++u) o[u] = keep[std::size_t(l[u])] ? 255 : 0;
  }
  return out;
}

/// Inliers of the plane (n, d): its 4-connected regions of at least 1/8 of the largest one's
/// size, on every `stride`-th pixel of every `stride`-th row (region pixel (v, u) is the cloud's
/// (stride v, stride u)).
cv::Mat inlier_region(const Cloud& cloud, const NormalMap& normals, const Eigen::Vector3d& n,
                      double d, double eps, double cos_dev, int stride = 1) {
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(near_plane(cloud, &normals, n, d, eps, cos_dev, stride), labels,
                                                     stats, centroids, 4, CV_32S);
  int best_area = 0;
  for (int k = 1; k < count; ++k) best_area = std::max(best_area, stats.at<int>(k, cv::CC_STAT_AREA));
  // the largest region and the pieces of the same plane that objects standing on it cut off
  std::vector<std::uint8_t> keep(std::size_t(count), 0);
  for (int k = 1; k < count; ++k) keep[std::size_t(k)] = 8 * stats.at<int>(k, cv::CC_STAT_AREA) >= best_area;
  return kept_labels(labels, keep);  // 255 where selected
}

/// The plane's extent: the pixels within the inlier distance of (n, d), whatever their normals,
/// 4-connected to its inlier region (255 where selected). Active-stereo normals are wavy: the
/// inliers with agreeing normals leave a filigree that covers a part of the table only.
cv::Mat extent_region(const Cloud& cloud, const cv::Mat& region, const Eigen::Vector3d& n, double d, double eps) {
  cv::Mat labels;
  const int count = cv::connectedComponents(near_plane(cloud, nullptr, n, d, eps, 0, 1), labels, 4, CV_32S);
  std::vector<std::uint8_t> keep(std::size_t(count), 0);
  for (int v = 0; v < labels.rows; ++v) {
    const int* l = labels.ptr<int>(v);
    const std::uint8_t* r = region.ptr<std::uint8_t>(v);
    for (int u = 0; u < labels.cols; ++u)
      if (r[u]) keep[std::size_t(l[u])] = 1;
  }
  keep[0] = 0;
  return kept_labels(labels, keep);
}

/// PCA plane of the masked points (of a region on every `stride`-th pixel): returns the RMS
/// distance; n oriented with d > 0; count is the region's pixels.
double fit_plane(const Cloud& cloud, const cv::Mat& region, Eigen::Vector3d& n, double& d,
                 Eigen::Vector3d& centroid, std::size_t& count, int stride = 1) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
  count = 0;
  for (int v = 0; v < region.rows; ++v) {
    const std::uint8_t* m = region.ptr<std::uint8_t>(v);
    for (int u = 0; u < region.cols; ++u) {
      if (!m[u]) continue;
      const float* p = cloud.ptr(stride * v, stride * u);
      const Eigen::Vector3d x(p[0], p[1], p[2]);
      s += x;
      ss += x * x.transpose();
      ++count;
    }
  }
  if (count < 3) return INFINITY;
  centroid = s / double(count);
  const Eigen::Matrix3d C = ss / double(count) - centroid * centroid.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  n = es.eigenvectors().col(0).normalized();
  d = -n.dot(centroid);
  if (d < 0) n = -n, d = -d;
  return std::sqrt(std::max(0.0, es.eigenvalues()(0)));
}

/// The support plane with the inlier region `region` of the plane (n, d): its mask (at full
/// resolution only), its world frame and its polygon (roi, rms and inlier_count are the
/// caller's). `stride` as inlier_region's. `extent` (full resolution), when given, is the region
/// the polygon bounds instead of the inliers.
SupportPlane plane_with_polygon(const Cloud& cloud, const cv::Mat& region, const Eigen::Vector3d& n,
                                double d, const Eigen::Vector3d& centroid, int stride = 1,
                                const cv::Mat* extent = nullptr) {
  const int H = region.rows, W = region.cols;
  SupportPlane out;
  out.normal = n;
  out.d = d;
  if (stride == 1) {
    out.inliers = Mask(H, W, 0);
    for (int v = 0; v < H; ++v) {
      const std::uint8_t* m = region.ptr<std::uint8_t>(v);
      for (int u = 0; u < W; ++u) out.inliers(v, u) = m[u] ? 1 : 0;
    }
  }

  // world frame: z = normal, x = camera x projected on the plane, origin = centroid on the plane
  const Eigen::Vector3d origin = centroid - n * (n.dot(centroid) + d);
  Eigen::Vector3d ex = Eigen::Vector3d::UnitX() - n * n.x();
  if (ex.norm() < 1e-6) ex = Eigen::Vector3d::UnitY() - n * n.y();
  ex.normalize();
  const Eigen::Vector3d ey = n.cross(ex);
  Eigen::Matrix3d camera_from_world;
  camera_from_world << ex, ey, n;
  Pose T = Pose::Identity();
  T.linear() = camera_from_world.transpose();
  T.translation() = -camera_from_world.transpose() * origin;
  out.world_from_camera = T;

  // polygon: convex hull of the region in plane coordinates. The image and the plane are related
  // by a homography, which maps convex sets to convex sets, so the hull is that of the first and
  // last region pixel of every row (at most 2 H points instead of the whole region).
  std::vector<cv::Point2f> pts;
  const cv::Mat& bounded = extent ? *extent : region;
  for (int v = 0; v < H; ++v) {
    const std::uint8_t* m = bounded.ptr<std::uint8_t>(v);
    int first = -1, last = -1;
    for (int u = 0; u < W; ++u)
      if (m[u]) {
        if (first < 0) first = u;
        last = u;
      }
    if (first < 0) continue;
    for (int u : {first, last}) {
      const float* p = cloud.ptr(stride * v, stride * u);
      const Eigen::Vector3d w = T * Eigen::Vector3d(p[0], p[1], p[2]);
      pts.emplace_back(float(w.x()), float(w.y()));
    }
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(pts, hull, /*clockwise=*/false);
  const Pose C = T.inverse();
  for (const auto& h : hull) out.polygon.push_back(C * Eigen::Vector3d(h.x, h.y, 0.0));
  return out;
}

/// The plane's polygon in its own coordinates (world x, y).
std::vector<Eigen::Vector2d> polygon_2d(const SupportPlane& plane) {
  std::vector<Eigen::Vector2d> poly;
  for (const auto& x : plane.polygon) poly.push_back((plane.world_from_camera * x).head<2>());
  return poly;
}

/// Twice the signed area of a polygon (positive: counter-clockwise).
double signed_area2(const std::vector<Eigen::Vector2d>& poly) {
  double area2 = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  return area2;
}

/// Area of the plane's polygon, square metres.
double polygon_area(const SupportPlane& plane) { return std::abs(signed_area2(polygon_2d(plane))) / 2; }

/// The middle half of the view in both directions: what the camera looks at.
inline bool central(int u, int v, int W, int H) {
  return std::abs(u - W / 2) < W / 4 && std::abs(v - H / 2) < H / 4;
}

/// region_above on every `stride`-th pixel of every `stride`-th row (the others stay 0).
Mask region_above_strided(const Cloud& cloud, const SupportPlane& plane, double min_height,
                          double max_height, double margin, int stride) {
  const int H = cloud.rows(), W = cloud.cols();
  Mask roi(H, W, 0);
  if (plane.polygon.size() < 3) return roi;
  // the polygon in plane coordinates (world x, y), counter-clockwise
  const Pose& T = plane.world_from_camera;
  std::vector<Eigen::Vector2d> poly = polygon_2d(plane);
  if (signed_area2(poly) < 0) std::reverse(poly.begin(), poly.end());
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  tbb::parallel_for(tbb::blocked_range<int>(0, (H + stride - 1) / stride, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin() * stride; v < rows.end() * stride; v += stride) {
      for (int u = 0; u < W; u += stride) {
        const float* p = cloud.ptr(v, u);
        if (!valid_point(p)) continue;
        const Eigen::Vector3f w = R * Eigen::Vector3f(p[0], p[1], p[2]) + t;
        if (w.z() < min_height * std::max(1.f, p[2] * p[2]) || w.z() > max_height) continue;
        bool inside = true;
        for (std::size_t i = 0; i < poly.size() && inside; ++i) {
          const Eigen::Vector2d& a = poly[i];
          const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - a;
          const double len = e.norm();
          if (len <= 0) continue;
          const double side = (e.x() * (w.y() - a.y()) - e.y() * (w.x() - a.x())) / len;
          inside = side >= margin;
        }
        if (inside) roi(v, u) = 1;
      }
    }
  });
  return roi;
}

}  // namespace

Mask region_above(const Cloud& cloud, const SupportPlane& plane, double min_height,
                  double max_height, double margin) {
  return region_above_strided(cloud, plane, min_height, max_height, margin, 1);
}

SupportPlane find_support_plane(const Cloud& cloud, const NormalMap& normals,
                                const SupportPlaneOptions& o) {
  if (!cloud.same_size(normals))
    throw InputError("support plane: cloud " + std::to_string(cloud.cols()) + "x" +
                     std::to_string(cloud.rows()) + " and normals " + std::to_string(normals.cols()) +
                     "x" + std::to_string(normals.rows()) + " differ in size");
  if (o.step < 1 || o.hypotheses < 1 || !(o.epsilon > 0) || o.max_height <= o.min_height)
    throw InputError("support plane: step, hypotheses and epsilon must be positive and "
                     "max_height > min_height");
  const int H = cloud.rows(), W = cloud.cols();
  Eigen::Vector3d up = o.up ? o.up->normalized() : Eigen::Vector3d(0, -1, 0);
  const double cos_tilt = std::cos((o.up ? o.max_tilt_deg : o.max_tilt_deg_unknown) * kDeg);
  const double cos_dev = std::cos(o.normal_deviation_deg * kDeg);

  // grid samples with a valid point and normal
  std::vector<Sample> samples;
  for (int v = o.step / 2; v < H; v += o.step)
    for (int u = o.step / 2; u < W; u += o.step) {
      const float* p = cloud.ptr(v, u);
      const float* n = normals.ptr(v, u);
      if (!valid_point(p) || !std::isfinite(n[0])) continue;
      samples.push_back({Eigen::Vector3f(p[0], p[1], p[2]), Eigen::Vector3f(n[0], n[1], n[2]), central(u, v, W, H)});
    }
  const std::size_t min_grid = std::size_t(o.min_inliers) / std::size_t(o.step * o.step);
  if (samples.size() < std::max<std::size_t>(min_grid, 3))
    throw InputError("support plane: too few valid points (" + std::to_string(samples.size()) +
                     " on the grid); the frame is empty or all NaN");

  // hypotheses: seed samples whose normal is near `up` (drawn in order from the seed)
  std::vector<int> seeds;
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<std::size_t> pick(0, samples.size() - 1);
  for (int tries = 0; tries < o.hypotheses * 20 && int(seeds.size()) < o.hypotheses; ++tries) {
    const std::size_t i = pick(rng);
    if (samples[i].n.cast<double>().dot(up) >= cos_tilt) seeds.push_back(int(i));
  }
  if (seeds.empty())
    throw InputError("support plane: no surface faces up (within the tilt limit); no table in view");
  std::vector<double> score(seeds.size(), 0.0);
  std::vector<std::size_t> support(seeds.size(), 0);
  const float eps = float(o.epsilon), cdev = float(cos_dev);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeds.size(), 4),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t h = r.begin(); h < r.end(); ++h) {
                        const Sample& s = samples[std::size_t(seeds[h])];
                        const Eigen::Vector3f n = s.n;
                        const float d = -n.dot(s.p);
                        std::size_t all = 0, central = 0;
                        for (const Sample& x : samples) {
                          const float z = x.p.z();
                          if (std::abs(n.dot(x.p) + d) > eps * std::max(z * z, 0.5f)) continue;
                          if (std::abs(n.dot(x.n)) < cdev) continue;
                          ++all;
                          central += x.central;
                        }
                        support[h] = all;
                        score[h] = double(all) + 3.0 * double(central);
                      }
                    });
  // Candidate planes: the best hypotheses, one per distinct plane (non-maximum suppression),
  // each refitted to its full-resolution connected region.
  std::vector<std::size_t> order(seeds.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
  struct Candidate {
    Eigen::Vector3d n, centroid;
    double d = 0, weight = 0, area = 0;
    std::size_t seed = 0;  ///< index of its hypothesis
    cv::Mat region;
    std::size_t count = 0;
  };
  std::vector<Candidate> candidates;
  std::size_t best_support = 0;
  for (std::size_t h : order) {
    if (int(candidates.size()) >= o.candidates) break;
    best_support = std::max(best_support, support[h]);
    if (support[h] < min_grid) break;
    const Sample& s = samples[std::size_t(seeds[h])];
    const auto taken = [&](const Eigen::Vector3d& x) {  // x lies on a plane already taken
      for (const Candidate& c : candidates)
        if (std::abs(c.n.dot(x) + c.d) < 3 * tolerance(o.epsilon, x.z())) return true;
      return false;
    };
    if (taken(s.p.cast<double>())) continue;
    // a plane weighs at most 8 times its pixels (4 near the centre, as many standing on it): one
    // too small to reach min_share of the heaviest so far is not refitted (1.5: grid sampling)
    double heaviest = 0;
    for (const Candidate& c : candidates) heaviest = std::max(heaviest, c.count ? c.weight : 0.0);
    if (8 * 1.5 * double(support[h] * std::size_t(o.step * o.step)) < o.min_share * heaviest) continue;
    // weighed on every second pixel of every second row (kStride); the chosen one is then
    // refitted at full resolution from its seed
    constexpr int kStride = 2;
    Candidate c;
    c.seed = h;
    c.n = s.n.cast<double>().normalized();
    c.d = -c.n.dot(s.p.cast<double>());
    c.region = inlier_region(cloud, normals, c.n, c.d, o.epsilon, cos_dev, kStride);
    fit_plane(cloud, c.region, c.n, c.d, c.centroid, c.count, kStride);
    c.count *= kStride * kStride;
    if (c.count >= 3 && taken(c.centroid)) continue;  // refitted onto a plane already taken
    if (c.count < std::size_t(o.min_inliers) || c.n.dot(up) < cos_tilt) {
      candidates.push_back(std::move(c));  // kept so that its plane is not tried again
      candidates.back().count = 0;
      continue;
    }
    // what the camera looks at: the plane's pixels and the points standing on it (at most as
    // many as the plane's: a wall has a room in front of it), those near the centre of the view
    // counted four times
    const SupportPlane plane = plane_with_polygon(cloud, c.region, c.n, c.d, c.centroid, kStride);
    c.area = polygon_area(plane);
    const Mask roi = region_above_strided(cloud, plane, o.min_height, o.max_height, o.margin, kStride);
    double on_plane = 0, above = 0;
    for (int v = 0; v < H; v += kStride) {
      const std::uint8_t* m = c.region.ptr<std::uint8_t>(v / kStride);
      for (int u = 0; u < W; u += kStride) {
        const double w = central(u, v, W, H) ? 4.0 : 1.0;
        if (m[u / kStride]) on_plane += w;
        else if (roi(v, u)) above += w;
      }
    }
    c.weight = on_plane + std::min(above, on_plane);
    candidates.push_back(std::move(c));
  }
  // Among planes parallel to each other, the highest one that carries a fair share of what is in
  // view is the support (a table over the floor, a desk over a larger carpet).
  const Candidate* chosen = nullptr;
  double max_weight = 0;
  for (const Candidate& c : candidates) max_weight = std::max(max_weight, c.count ? c.weight : 0.0);
  for (const Candidate& c : candidates) {
    if (!c.count || c.weight < o.min_share * max_weight) continue;
    const bool parallel = chosen && c.n.dot(chosen->n) > std::cos(10 * kDeg);
    if (!chosen || (parallel && c.area >= o.min_area ? c.d < chosen->d : c.weight > chosen->weight))
      chosen = &c;
  }
  if (!chosen) {
    std::size_t largest = 0;
    for (const Candidate& c : candidates) largest = std::max(largest, std::size_t(cv::countNonZero(c.region)));
    if (best_support < min_grid)
      throw InputError("support plane: the best plane has " + std::to_string(best_support * o.step * o.step) +
                       " points, fewer than min_inliers = " + std::to_string(o.min_inliers));
    throw InputError("support plane: the plane's region has " + std::to_string(largest) +
                     " points, fewer than min_inliers = " + std::to_string(o.min_inliers));
  }
  // the chosen plane refitted at full resolution from its seed, then with a tighter tolerance
  const Sample& seed = samples[std::size_t(seeds[chosen->seed])];
  Eigen::Vector3d n = seed.n.cast<double>().normalized(), centroid;
  double d = -n.dot(seed.p.cast<double>()), rms = 0;
  std::size_t count = 0;
  cv::Mat region;
  for (int round = 0; round < 2; ++round) {
    region = inlier_region(cloud, normals, n, d, round == 0 ? o.epsilon : 0.75 * o.epsilon, cos_dev);
    rms = fit_plane(cloud, region, n, d, centroid, count);
  }
  if (count < std::size_t(o.min_inliers))
    throw InputError("support plane: the plane's region has " + std::to_string(count) +
                     " points, fewer than min_inliers = " + std::to_string(o.min_inliers));
  const cv::Mat extent = extent_region(cloud, region, n, d, o.epsilon);
  SupportPlane out = plane_with_polygon(cloud, region, n, d, centroid, 1, &extent);
  out.rms = rms;
  out.inlier_count = count;
  out.roi = region_above(cloud, out, o.min_height, o.max_height, o.margin);
  return out;
}

}  // namespace mereo::extension
