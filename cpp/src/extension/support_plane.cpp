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

#include "core/components.hpp"
#include "core/vectorize.hpp"
#include "mereo/core/error.hpp"

namespace mereo::extension {
namespace {

constexpr double kDeg = M_PI / 180.0;
/// A region pixel this close to the image's border (pixels) lies on it.
constexpr int kBorderPx = 8;
/// Parallel planes closer than this (metres) are one support and what lies on it.
constexpr double kMinStep = 0.05;

/// Inlier tolerance at depth z: epsilon grows with z^2 (Kinect axial noise), never below
/// its value at 0.7 m.
template <typename T>
inline T tolerance(T epsilon, T z) { return epsilon * std::max(z * z, T(0.5)); }

/// A plane (n, d) and its inlier test, in float (eps: the tolerance at 1 m, where one applies).
struct PlaneTest {
  float nx, ny, nz, d, eps, cos_dev;
};

/// The grid samples (points with normals) in columns, with each point's inlier tolerance.
struct Grid {
  std::vector<float> x, y, z, nx, ny, nz, tol;
  std::vector<std::uint8_t> central;
  std::size_t size() const { return x.size(); }
};

/// How many of the n samples are inliers of the plane t (within their tolerance, normal within
/// acos(cos_dev)), and how many of those are central. Branch-free, so that it vectorizes.
MEREO_VECTOR_CLONES void count_inliers(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                                       const float* __restrict nx, const float* __restrict ny,
                                       const float* __restrict nz, const float* __restrict tol,
                                       const std::uint8_t* __restrict central, int n, PlaneTest t, int& all,
                                       int& in_centre) {
  int a = 0, c = 0;
  for (int i = 0; i < n; ++i) {
    const bool in = (std::abs(t.nx * x[i] + t.ny * y[i] + t.nz * z[i] + t.d) <= tol[i]) &
                    (std::abs(t.nx * nx[i] + t.ny * ny[i] + t.nz * nz[i]) >= t.cos_dev);
    a += in;
    c += in & central[i];
  }
  all = a, in_centre = c;
}

/// One row of near_plane: m[u] = 1 where the point p[S u] (S = 3 stride) is valid and within the
/// inlier distance of the plane; with normals q, also where |n . q[S u]| >= cos_dev. Branch-free
/// in float (a missing point or normal is NaN or out of range and fails the tests by itself).
template <int kStride>
MEREO_VECTOR_CLONES void near_plane_row(const float* __restrict p, const float* __restrict q,
                                        std::uint8_t* __restrict m, int n, PlaneTest t) {
  constexpr int S = 3 * kStride;
  for (int u = 0; u < n; ++u) {
    const float x = p[S * u], y = p[S * u + 1], z = p[S * u + 2];
    const bool near = std::abs(t.nx * x + t.ny * y + t.nz * z + t.d) <= tolerance(t.eps, z);
    m[u] = std::uint8_t(valid_point(x, y, z) & near);
  }
  if (q)
    for (int u = 0; u < n; ++u)
      m[u] &= std::uint8_t(std::abs(t.nx * q[S * u] + t.ny * q[S * u + 1] + t.nz * q[S * u + 2]) >= t.cos_dev);
}

/// The pixels (1) within the inlier distance of the plane (n, d) and, given normals, whose normal
/// is within acos(cos_dev) of n, on every `stride`-th pixel (1 or 2) of every `stride`-th row.
cv::Mat near_plane(const Cloud& cloud, const NormalMap* normals, const Eigen::Vector3d& n, double d, double eps,
                   double cos_dev, int stride) {
  const int H = (cloud.rows() + stride - 1) / stride, W = (cloud.cols() + stride - 1) / stride;
  cv::Mat mask(H, W, CV_8U);
  const PlaneTest t{float(n.x()), float(n.y()), float(n.z()), float(d), float(eps), float(cos_dev)};
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* p = cloud.ptr(stride * v, 0);
      const float* q = normals ? normals->ptr(stride * v, 0) : nullptr;
      std::uint8_t* m = mask.ptr<std::uint8_t>(v);
      if (stride == 1) near_plane_row<1>(p, q, m, W, t);
      else near_plane_row<2>(p, q, m, W, t);
    }
  });
  return mask;
}

/// Inliers of the plane (n, d): its 4-connected regions of at least 1/8 of the largest one's
/// size, on every `stride`-th pixel of every `stride`-th row (region pixel (v, u) is the cloud's
/// (stride v, stride u)); 255 where selected.
cv::Mat inlier_region(const Cloud& cloud, const NormalMap& normals, const Eigen::Vector3d& n,
                      double d, double eps, double cos_dev, int stride = 1) {
  const Components c = connected_components(near_plane(cloud, &normals, n, d, eps, cos_dev, stride));
  const std::size_t best_area = c.area.empty() ? 0 : *std::max_element(c.area.begin(), c.area.end());
  // the largest region and the pieces of the same plane that objects standing on it cut off
  std::vector<std::uint8_t> keep(c.area.size());
  for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = 8 * c.area[k] >= best_area;
  return draw_components(c, keep);
}

/// The plane's extent: the pixels within the inlier distance of (n, d), whatever their normals,
/// 4-connected to its inlier region (255 where selected). Active-stereo normals are wavy: the
/// inliers with agreeing normals leave a filigree that covers a part of the table only.
cv::Mat extent_region(const Cloud& cloud, const cv::Mat& region, const Eigen::Vector3d& n, double d, double eps) {
  const Components c = connected_components(near_plane(cloud, nullptr, n, d, eps, 0, 1));
  return draw_components(c, components_touching(c, region));
}

/// PCA plane of the masked points (of a region on every `stride`-th pixel): returns the RMS
/// distance; n oriented with d > 0; count is the region's pixels.
double fit_plane(const Cloud& cloud, const cv::Mat& region, Eigen::Vector3d& n, double& d,
                 Eigen::Vector3d& centroid, std::size_t& count, int stride = 1) {
  // sums of the coordinates and their products, per row about the row's first point (six
  // products per point, small values), then moved to the camera origin
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
  count = 0;
  for (int v = 0; v < region.rows; ++v) {
    const std::uint8_t* m = region.ptr<std::uint8_t>(v);
    const float* row = cloud.ptr(stride * v, 0);
    int first = 0;
    while (first < region.cols && !m[first]) ++first;
    if (first == region.cols) continue;
    const float* o = row + 3 * stride * first;
    const double ox = o[0], oy = o[1], oz = o[2];
    double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
    int k = 0;
    for (int u = first; u < region.cols; ++u) {
      if (!m[u]) continue;
      const float* p = row + 3 * stride * u;
      const double x = p[0] - ox, y = p[1] - oy, z = p[2] - oz;
      sx += x, sy += y, sz += z;
      sxx += x * x, sxy += x * y, sxz += x * z, syy += y * y, syz += y * z, szz += z * z;
      ++k;
    }
    // back to the camera origin: sum (o + x)(o + x)^T = k o o^T + o sx^T + sx o^T + sum x x^T
    const Eigen::Vector3d O(ox, oy, oz), S(sx, sy, sz);
    Eigen::Matrix3d X;
    X << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    s += double(k) * O + S;
    ss += double(k) * O * O.transpose() + O * S.transpose() + S * O.transpose() + X;
    count += std::size_t(k);
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
  // Each point remembers the image borders its pixel lies on (within kBorderPx: the filters
  // leave the outermost pixels without depth).
  std::vector<cv::Point2f> pts;
  std::vector<std::uint8_t> sides;
  const cv::Mat& bounded = extent ? *extent : region;
  const int full_w = cloud.cols(), full_h = cloud.rows();
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
      const int x = stride * u, y = stride * v;
      const float* p = cloud.ptr(y, x);
      const Eigen::Vector3d w = T * Eigen::Vector3d(p[0], p[1], p[2]);
      pts.emplace_back(float(w.x()), float(w.y()));
      sides.push_back(std::uint8_t((x <= kBorderPx ? SupportPlane::kLeft : 0) |
                                   (x >= full_w - 1 - kBorderPx ? SupportPlane::kRight : 0) |
                                   (y <= kBorderPx ? SupportPlane::kTop : 0) |
                                   (y >= full_h - 1 - kBorderPx ? SupportPlane::kBottom : 0)));
    }
  }
  std::vector<int> hull;
  if (!pts.empty()) cv::convexHull(pts, hull, /*clockwise=*/false, /*returnPoints=*/false);
  const Pose C = T.inverse();
  for (int i : hull) {
    out.polygon.push_back(C * Eigen::Vector3d(pts[std::size_t(i)].x, pts[std::size_t(i)].y, 0.0));
    out.borders.push_back(sides[std::size_t(i)]);
  }
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

/// One row of region_above's height test: band[u] = 1 where the point p[3 kStride u] is valid and
/// its height r . p + t above the plane lies in [lo max(1, z^2), hi]. Branch-free.
template <int kStride>
MEREO_VECTOR_CLONES void height_band_row(const float* __restrict p, std::uint8_t* __restrict band, int n,
                                         Eigen::Vector3f r, float t, float lo, float hi) {
  constexpr int S = 3 * kStride;
  for (int u = 0; u < n; ++u) {
    const float x = p[S * u], y = p[S * u + 1], z = p[S * u + 2];
    const float h = r.x() * x + r.y() * y + r.z() * z + t;
    band[u] = std::uint8_t(valid_point(x, y, z) & (h >= lo * std::max(1.f, z * z)) & (h <= hi));
  }
}

/// region_above on every `stride`-th pixel (1, 2 or 4) of every `stride`-th row (the others stay 0).
Mask region_above_strided(const Cloud& cloud, const SupportPlane& plane, double min_height,
                          double max_height, double margin, double beyond_border, int stride) {
  const int H = cloud.rows(), W = cloud.cols();
  Mask roi(H, W, 0);
  if (plane.polygon.size() < 3) return roi;
  // the polygon in plane coordinates (world x, y), counter-clockwise
  const Pose& T = plane.world_from_camera;
  std::vector<Eigen::Vector2d> poly = polygon_2d(plane);
  std::vector<std::uint8_t> borders = plane.borders;
  borders.resize(poly.size(), 0);
  if (signed_area2(poly) < 0) {
    std::reverse(poly.begin(), poly.end());
    std::reverse(borders.begin(), borders.end());
  }
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  // each edge as a line a x + b y + c = signed distance to its left (inside), a, b of unit
  // length; a point is inside by `margin`, or up to beyond_border outside an edge on the border
  struct Edge {
    float a, b, c, inside_by;
  };
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const std::size_t j = (i + 1) % poly.size();
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d e = poly[j] - p;
    const double len = e.norm();
    if (len <= 0) continue;
    const double a = -e.y() / len, b = e.x() / len;
    const bool open = (borders[i] & borders[j]) != 0;
    edges.push_back({float(a), float(b), float(-(a * p.x() + b * p.y())), float(open ? -beyond_border : margin)});
  }
  const float lo = float(min_height), hi = float(max_height);
  const int n = (W + stride - 1) / stride;  // sampled pixels per row
  tbb::parallel_for(tbb::blocked_range<int>(0, (H + stride - 1) / stride, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<std::uint8_t> band(static_cast<std::size_t>(n));
    for (int v = rows.begin() * stride; v < rows.end() * stride; v += stride) {
      const float* row = cloud.ptr(v, 0);
      if (stride == 1) height_band_row<1>(row, band.data(), n, R.row(2), t.z(), lo, hi);
      else if (stride == 2) height_band_row<2>(row, band.data(), n, R.row(2), t.z(), lo, hi);
      else height_band_row<4>(row, band.data(), n, R.row(2), t.z(), lo, hi);
      for (int k = 0; k < n; ++k) {
        if (!band[std::size_t(k)]) continue;
        const float* p = row + 3 * stride * k;
        const float x = R(0, 0) * p[0] + R(0, 1) * p[1] + R(0, 2) * p[2] + t.x(),
                    y = R(1, 0) * p[0] + R(1, 1) * p[1] + R(1, 2) * p[2] + t.y();
        bool inside = true;
        for (const Edge& e : edges)
          if (e.a * x + e.b * y + e.c < e.inside_by) {
            inside = false;
            break;
          }
        if (inside) roi(v, stride * k) = 1;
      }
    }
  });
  return roi;
}

/// SupportPlane::noise of `plane` (whose polygon is set): over the points within a band of kBand
/// about the plane (wide enough not to cut the noise's tails off; the plane's own inlier test would)
/// and kInside inside its polygon (off the table's edges), on every 4th pixel of every 4th row,
/// leaving out those whose normal turns more than 60 degrees from the plane's (an object's wall
/// standing on it) and those seen at a grazing angle; of these, the farthest quarter: a sensor's
/// noise has a floor that z^2 does not model, and the far points tell how it grows where the
/// objects are hard to see (rendered Kinect-like depth: 4.4 mm/m^2 at 0.5-0.8 m, 2.3 at 1-1.2 m).
double depth_noise(const Cloud& cloud, const NormalMap& normals, const SupportPlane& plane) {
  constexpr double kBand = 0.03, kInside = 0.02, kMinCos = 0.5, kMinRayCos = 0.3;
  constexpr std::size_t kMinPoints = 100;  // of the farthest quarter
  constexpr int kStride = 4;
  const Mask band = region_above_strided(cloud, plane, -kBand, kBand, kInside, 0.0, kStride);
  std::vector<std::pair<double, double>> samples;  // (depth, the error along the ray scaled to 1 m)
  for (int v = 0; v < cloud.rows(); v += kStride)
    for (int u = 0; u < cloud.cols(); u += kStride) {
      if (!band(v, u)) continue;
      const float* p = cloud.ptr(v, u);
      const float* q = normals.ptr(v, u);
      const Eigen::Vector3d x(p[0], p[1], p[2]), m(q[0], q[1], q[2]);
      if (m.allFinite() && std::abs(m.dot(plane.normal)) < kMinCos) continue;
      // a depth error dz moves the point along its ray by x dz / z: its height by n.x dz / z
      const double z = x.z(), nx = std::abs(plane.normal.dot(x));
      if (z <= 0 || nx < kMinRayCos * x.norm()) continue;
      samples.emplace_back(z, plane.height(x) / (nx * z));
    }
  if (samples.size() < 4 * kMinPoints) return 0.0;
  const auto far = samples.begin() + std::ptrdiff_t(samples.size() * 3 / 4);
  std::nth_element(samples.begin(), far, samples.end());
  // the spread below the densest half (the middle of the shortest interval holding half of them):
  // what stands on the plane (a plate's bottom, the foot of a wall whose normals stereo depth
  // turns, depth smeared past an object's silhouette) lies above the table, and a far part of the
  // table may lie a little off the plane fitted to all of it; below that middle lies the noise
  // alone, and the median distance of a half-normal is 0.6745 of its deviation (the median
  // absolute deviation gave 9.5 and 3.9 mm at 1 m on rendered stereo 1380 and 1383, for a
  // model's 6.0)
  std::vector<double> e;
  for (auto it = far; it != samples.end(); ++it) e.push_back(it->second);
  std::sort(e.begin(), e.end());
  const std::size_t half = e.size() / 2;
  std::size_t at = 0;
  for (std::size_t i = 0; i + half < e.size(); ++i)
    if (e[i + half] - e[i] < e[at + half] - e[at]) at = i;
  const double centre = 0.5 * (e[at] + e[at + half]);
  std::vector<double> below;
  for (double x : e)
    if (x < centre) below.push_back(centre - x);
  if (below.size() < kMinPoints / 2) return 0.0;
  const auto mid = below.begin() + std::ptrdiff_t(below.size() / 2);
  std::nth_element(below.begin(), mid, below.end());
  // then their RMS within 3.5 deviations of that first guess: the median of quantized depth
  // (structured light's disparity steps are as coarse as its noise beyond a metre) jumps between
  // the steps, the mean of squares does not
  const double first = *mid / 0.6745;
  double ss = 0;
  std::size_t n = 0;
  for (double x : below)
    if (x <= 3.5 * first) ss += x * x, ++n;
  return n ? std::sqrt(ss / double(n)) : 0.0;
}

}  // namespace

Mask region_above(const Cloud& cloud, const SupportPlane& plane, double min_height,
                  double max_height, double margin, double beyond_border) {
  return region_above_strided(cloud, plane, min_height, max_height, margin, beyond_border, 1);
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
  Grid grid;
  for (int v = o.step / 2; v < H; v += o.step)
    for (int u = o.step / 2; u < W; u += o.step) {
      const float* p = cloud.ptr(v, u);
      const float* n = normals.ptr(v, u);
      if (!valid_point(p) || !std::isfinite(n[0])) continue;
      grid.x.push_back(p[0]), grid.y.push_back(p[1]), grid.z.push_back(p[2]);
      grid.nx.push_back(n[0]), grid.ny.push_back(n[1]), grid.nz.push_back(n[2]);
      grid.tol.push_back(tolerance(float(o.epsilon), p[2]));
      grid.central.push_back(central(u, v, W, H));
    }
  const auto point = [&](std::size_t i) { return Eigen::Vector3f(grid.x[i], grid.y[i], grid.z[i]); };
  const auto normal = [&](std::size_t i) { return Eigen::Vector3f(grid.nx[i], grid.ny[i], grid.nz[i]); };
  const std::size_t min_grid = std::size_t(o.min_inliers) / std::size_t(o.step * o.step);
  if (grid.size() < std::max<std::size_t>(min_grid, 3))
    throw InputError("support plane: too few valid points (" + std::to_string(grid.size()) +
                     " on the grid); the frame is empty or all NaN");

  // hypotheses: seed samples whose normal is near `up` (drawn in order from the seed)
  std::vector<int> seeds;
  std::mt19937_64 rng(o.seed);
  std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
  for (int tries = 0; tries < o.hypotheses * 20 && int(seeds.size()) < o.hypotheses; ++tries) {
    const std::size_t i = pick(rng);
    if (normal(i).cast<double>().dot(up) >= cos_tilt) seeds.push_back(int(i));
  }
  if (seeds.empty())
    throw InputError("support plane: no surface faces up (within the tilt limit); no table in view");
  std::vector<double> score(seeds.size(), 0.0);
  std::vector<std::size_t> support(seeds.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeds.size(), 4), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t h = r.begin(); h < r.end(); ++h) {
      const Eigen::Vector3f n = normal(std::size_t(seeds[h]));
      const PlaneTest t{n.x(), n.y(), n.z(), -n.dot(point(std::size_t(seeds[h]))), 0.f, float(cos_dev)};
      int all = 0, in_centre = 0;
      count_inliers(grid.x.data(), grid.y.data(), grid.z.data(), grid.nx.data(), grid.ny.data(), grid.nz.data(),
                    grid.tol.data(), grid.central.data(), int(grid.size()), t, all, in_centre);
      support[h] = std::size_t(all);
      score[h] = double(all) + 3.0 * double(in_centre);
    }
  });
  // Candidate planes: the best hypotheses, one per distinct plane (non-maximum suppression),
  // each refitted to its full-resolution connected region.
  std::vector<std::size_t> order(seeds.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
  struct Candidate {
    Eigen::Vector3d n, centroid;
    Eigen::Vector3d seed_p, seed_n;  ///< its hypothesis: a grid point and its normal
    double d = 0, weight = 0, area = 0;
    cv::Mat region;
    std::size_t count = 0;
  };
  std::vector<Candidate> candidates;
  std::size_t best_support = 0;
  for (std::size_t h : order) {
    if (int(candidates.size()) >= o.candidates) break;
    best_support = std::max(best_support, support[h]);
    if (support[h] < min_grid) break;
    const Eigen::Vector3f seed_p = point(std::size_t(seeds[h])), seed_n = normal(std::size_t(seeds[h]));
    const auto taken = [&](const Eigen::Vector3d& x) {  // x lies on a plane already taken
      for (const Candidate& c : candidates)
        if (std::abs(c.n.dot(x) + c.d) < 3 * tolerance(o.epsilon, x.z())) return true;
      return false;
    };
    if (taken(seed_p.cast<double>())) continue;
    // a plane weighs at most 8 times its pixels (4 near the centre, as many standing on it): one
    // too small to reach min_share of the heaviest so far is not refitted (1.5: grid sampling)
    double heaviest = 0;
    for (const Candidate& c : candidates) heaviest = std::max(heaviest, c.count ? c.weight : 0.0);
    if (8 * 1.5 * double(support[h] * std::size_t(o.step * o.step)) < o.min_share * heaviest) continue;
    // weighed on every second pixel of every second row (kStride); the chosen one is then
    // refitted at full resolution from its seed
    constexpr int kStride = 2;
    Candidate c;
    c.seed_p = seed_p.cast<double>(), c.seed_n = seed_n.cast<double>().normalized();
    c.n = c.seed_n;
    c.d = -c.n.dot(c.seed_p);
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
    const Mask roi = region_above_strided(cloud, plane, o.min_height, o.max_height, o.margin, o.beyond_border, kStride);
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
  // Among planes parallel to each other and a step apart, the highest one that carries a fair
  // share of what is in view is the support (a table over the floor, a desk over a larger
  // carpet); of planes closer than that (a plate or a tray on the table), the heavier.
  const Candidate* chosen = nullptr;
  double max_weight = 0;
  for (const Candidate& c : candidates) max_weight = std::max(max_weight, c.count ? c.weight : 0.0);
  for (const Candidate& c : candidates) {
    if (!c.count || c.weight < o.min_share * max_weight) continue;
    const bool parallel = chosen && c.n.dot(chosen->n) > std::cos(10 * kDeg);
    const bool stepped = chosen && std::abs(c.d - chosen->d) >= kMinStep;
    // the higher of two stepped planes must itself be large enough to be a support, whichever
    // of them came first (a box's top in front of the table is not)
    const Candidate* higher = chosen && c.d < chosen->d ? &c : chosen;
    const Candidate* lower = higher == &c ? chosen : &c;
    const Candidate* preferred = o.prefer == SupportPlaneOptions::Prefer::Highest ? higher : lower;
    const bool by_height = parallel && stepped && preferred->area >= o.min_area;
    if (!chosen || (by_height ? preferred == &c : c.weight > chosen->weight)) chosen = &c;
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
  Eigen::Vector3d n = chosen->seed_n, centroid;
  double d = -n.dot(chosen->seed_p), rms = 0;
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
  out.noise = depth_noise(cloud, normals, out);
  out.roi = region_above(cloud, out, o.min_height, o.max_height, o.margin, o.beyond_border);
  return out;
}

}  // namespace mereo::extension
