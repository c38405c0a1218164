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
  cv::Mat out(labels.rows, labels.cols, CV_8U);
  tbb::parallel_for(tbb::blocked_range<int>(0, labels.rows, 32), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const int* l = labels.ptr<int>(v);
      std::uint8_t* o = out.ptr<std::uint8_t>(v);
      for (int u = 0; u < labels.cols; ++u) o[u] = keep[std::size_t(l[u])] ? 255 : 0;
    }
  });
  return out;
}

/// Inliers of the plane (n, d): its 4-connected regions of at least 1/8 of the largest one's
/// size, on every `stride`-th pixel of every `stride`-th row (region pixel (v, u) is the cloud's
/// (stride v, stride u)).
cv::Mat inlier_region(const Cloud& cloud, const NormalMap& normals, const Eigen::Vector3d& n,
                      double d, double eps, double cos_dev, int stride = 1) {
  cv::Mat labels, stats, centroids;  // (Bolelli's Spaghetti labelling: OpenCV's fastest)
  const int count = cv::connectedComponentsWithStats(near_plane(cloud, &normals, n, d, eps, cos_dev, stride), labels,
                                                     stats, centroids, 4, CV_32S, cv::CCL_BOLELLI);
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
  const int count =
      cv::connectedComponents(near_plane(cloud, nullptr, n, d, eps, 0, 1), labels, 4, CV_32S, cv::CCL_BOLELLI);
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
/// distance; n oriented with d > 0; count is the region's pixels. The moments are summed over
/// fixed bands of rows in parallel, then over the bands in order (the same sum every run).
double fit_plane(const Cloud& cloud, const cv::Mat& region, Eigen::Vector3d& n, double& d,
                 Eigen::Vector3d& centroid, std::size_t& count, int stride = 1) {
  struct Moments {
    double s[3] = {0, 0, 0}, ss[6] = {0, 0, 0, 0, 0, 0};  // sums of x, y, z; xx, xy, xz, yy, yz, zz
    std::size_t count = 0;
  };
  constexpr int kBand = 16;
  std::vector<Moments> bands(std::size_t((region.rows + kBand - 1) / kBand));
  tbb::parallel_for(std::size_t(0), bands.size(), [&](std::size_t b) {
    Moments m;
    const int v1 = std::min(region.rows, int(b + 1) * kBand);
    for (int v = int(b) * kBand; v < v1; ++v) {
      const std::uint8_t* r = region.ptr<std::uint8_t>(v);
      for (int u = 0; u < region.cols; ++u) {
        if (!r[u]) continue;
        const float* p = cloud.ptr(stride * v, stride * u);
        const double x = p[0], y = p[1], z = p[2];
        m.s[0] += x, m.s[1] += y, m.s[2] += z;
        m.ss[0] += x * x, m.ss[1] += x * y, m.ss[2] += x * z, m.ss[3] += y * y, m.ss[4] += y * z, m.ss[5] += z * z;
        ++m.count;
      }
    }
    bands[b] = m;
  });
  Moments all;
  for (const Moments& m : bands) {
    for (int k = 0; k < 3; ++k) all.s[k] += m.s[k];
    for (int k = 0; k < 6; ++k) all.ss[k] += m.ss[k];
    all.count += m.count;
  }
  count = all.count;
  if (count < 3) return INFINITY;
  const double c = double(count);
  centroid = Eigen::Vector3d(all.s[0], all.s[1], all.s[2]) / c;
  Eigen::Matrix3d C;
  C << all.ss[0], all.ss[1], all.ss[2], all.ss[1], all.ss[3], all.ss[4], all.ss[2], all.ss[4], all.ss[5];
  C = C / c - centroid * centroid.transpose();
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

/// Whether plane points (world x, y) lie inside a convex counter-clockwise polygon shrunk by
/// `margin`: every edge's signed distance at least margin. A grid of cells over the polygon
/// answers for the cells wholly inside or wholly outside (the distances are 1-Lipschitz, so the
/// centre's tell for the cell within half its diagonal); points in the cells the border crosses
/// get the exact test.
class InsidePolygon {
 public:
  InsidePolygon(const std::vector<Eigen::Vector2d>& poly, double margin) : margin_(margin) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - poly[i];
      if (e.norm() > 0) edges_.push_back({poly[i], e, e.norm()});
    }
    lo_ = hi_ = poly.front();
    for (const auto& x : poly) lo_ = lo_.cwiseMin(x), hi_ = hi_.cwiseMax(x);
    lo_ -= Eigen::Vector2d::Constant(1e-6), hi_ += Eigen::Vector2d::Constant(1e-6);
    cell_ = std::max({0.02, (hi_.x() - lo_.x()) / kMaxCells, (hi_.y() - lo_.y()) / kMaxCells});
    nx_ = int((hi_.x() - lo_.x()) / cell_) + 1, ny_ = int((hi_.y() - lo_.y()) / cell_) + 1;
    const double reach = cell_ * std::sqrt(0.5) + 1e-9;  // half a cell's diagonal
    state_.assign(std::size_t(nx_) * std::size_t(ny_), kBorder);
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i) {
        const Eigen::Vector2d c = lo_ + cell_ * Eigen::Vector2d(i + 0.5, j + 0.5);
        double m = INFINITY;
        for (const Edge& e : edges_) m = std::min(m, side(e, c.x(), c.y()));
        state_[std::size_t(j) * nx_ + i] = m - reach >= margin_ ? kInside : m + reach < margin_ ? kOutside : kBorder;
      }
  }
  bool operator()(double x, double y) const {
    if (x >= lo_.x() && x < hi_.x() && y >= lo_.y() && y < hi_.y()) {
      const std::size_t i = std::size_t((x - lo_.x()) / cell_), j = std::size_t((y - lo_.y()) / cell_);
      if (state_[j * std::size_t(nx_) + i] != kBorder) return state_[j * std::size_t(nx_) + i] == kInside;
    } else if (margin_ >= 0) {
      return edges_.empty();  // (a polygon grown by -margin reaches beyond its vertices' box)
    }
    for (const Edge& e : edges_)
      if (side(e, x, y) < margin_) return false;
    return true;
  }

 private:
  struct Edge {
    Eigen::Vector2d a, e;  // a vertex, the edge to the next
    double len;
  };
  static constexpr std::uint8_t kInside = 0, kOutside = 1, kBorder = 2;
  static constexpr double kMaxCells = 48;
  /// The signed distance of (x, y) from the edge's line, positive inside (as region_above had it).
  static double side(const Edge& e, double x, double y) {
    return (e.e.x() * (y - e.a.y()) - e.e.y() * (x - e.a.x())) / e.len;
  }
  double margin_;
  std::vector<Edge> edges_;
  Eigen::Vector2d lo_, hi_;
  double cell_ = 0.005;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> state_;
};

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
  const InsidePolygon inside(poly, margin);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  tbb::parallel_for(tbb::blocked_range<int>(0, (H + stride - 1) / stride, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin() * stride; v < rows.end() * stride; v += stride) {
      for (int u = 0; u < W; u += stride) {
        const float* p = cloud.ptr(v, u);
        if (!valid_point(p)) continue;
        const Eigen::Vector3f w = R * Eigen::Vector3f(p[0], p[1], p[2]) + t;
        if (w.z() < min_height * std::max(1.f, p[2] * p[2]) || w.z() > max_height) continue;
        if (inside(w.x(), w.y())) roi(v, u) = 1;
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
  // the samples' coordinates, normals and tolerances as arrays: the scoring loop below runs
  // 200 hypotheses over every sample, branch-free and vectorized
  const std::size_t S = samples.size();
  std::vector<float> px(S), py(S), pz(S), nx(S), ny(S), nz(S), tol(S);
  std::vector<std::uint8_t> in_centre(S);
  for (std::size_t i = 0; i < S; ++i) {
    const Sample& x = samples[i];
    px[i] = x.p.x(), py[i] = x.p.y(), pz[i] = x.p.z(), nx[i] = x.n.x(), ny[i] = x.n.y(), nz[i] = x.n.z();
    tol[i] = eps * std::max(x.p.z() * x.p.z(), 0.5f), in_centre[i] = x.central;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeds.size(), 4),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t h = r.begin(); h < r.end(); ++h) {
                        const Sample& s = samples[std::size_t(seeds[h])];
                        const float a = s.n.x(), b = s.n.y(), c = s.n.z(), d = -s.n.dot(s.p);
                        std::uint32_t all = 0, central = 0;
                        for (std::size_t i = 0; i < S; ++i) {
                          const bool in = std::abs(a * px[i] + b * py[i] + c * pz[i] + d) <= tol[i] &&
                                          std::abs(a * nx[i] + b * ny[i] + c * nz[i]) >= cdev;
                          all += in;
                          central += in & (in_centre[i] != 0);
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
  // the chosen plane (refitted to its region on the half-resolution grid) refitted at full
  // resolution with a tighter tolerance
  Eigen::Vector3d n = chosen->n, centroid;
  double d = chosen->d;
  std::size_t count = 0;
  const cv::Mat region = inlier_region(cloud, normals, n, d, 0.75 * o.epsilon, cos_dev);
  const double rms = fit_plane(cloud, region, n, d, centroid, count);
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
