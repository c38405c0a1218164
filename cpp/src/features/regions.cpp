// Free-form regions above the support (mereo/features/regions.hpp).
#include "mereo/features/regions.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "features/pixels.hpp"
#include "mereo/core/error.hpp"

namespace mereo::features {
namespace {

using detail::quantile;

/// The upright box of a region's world points (z up from the support), robust to a few stray
/// points: the 2nd to 98th percentiles.
shapes::Region box_of(const std::vector<Eigen::Vector3d>& w, double neck_share) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : w) mean += p.head<2>();
  mean /= double(w.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : w) cov += (p.head<2>() - mean) * (p.head<2>() - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d major = eig.eigenvectors().col(1), minor = eig.eigenvectors().col(0);
  std::vector<double> a, b, z;
  for (const auto& p : w) a.push_back(major.dot(p.head<2>())), b.push_back(minor.dot(p.head<2>())), z.push_back(p.z());
  const double a0 = quantile(a, 0.02), a1 = quantile(a, 0.98), b0 = quantile(b, 0.02), b1 = quantile(b, 0.98);
  const double top = std::max(0.0, quantile(z, 0.98)), foot = std::max(0.0, quantile(z, 0.02));
  shapes::Region r;
  r.width = a1 - a0, r.thickness = b1 - b0, r.height = top, r.foot = foot;
  const Eigen::Vector2d c = major * (a0 + a1) / 2 + minor * (b0 + b1) / 2;
  r.point = Eigen::Vector3d(c.x(), c.y(), top / 2);
  r.axis = Eigen::Vector3d::UnitZ();
  r.width_axis = Eigen::Vector3d(major.x(), major.y(), 0);
  // the neck: the width of the top slice over the region's width
  std::vector<double> slice;
  for (const auto& p : w)
    if (p.z() >= top * (1 - neck_share) && p.z() <= top) slice.push_back(major.dot(p.head<2>()));
  if (slice.size() >= 10 && r.width > 0) r.neck = (quantile(slice, 0.95) - quantile(slice, 0.05)) / r.width;
  return r;
}

}  // namespace

std::optional<Segment> describe_region(const Cloud& cloud, const extension::SupportPlane& plane,
                                       std::vector<int> pixels, const RegionOptions& o, const ColorImage* color) {
  const int W = cloud.cols();
  const Pose& T = plane.world_from_camera;
  std::vector<Eigen::Vector3d> w;
  w.reserve(pixels.size());
  for (int i : pixels) {
    const float* q = cloud.ptr(i / W, i % W);
    if (valid_point(q)) w.push_back(T * Eigen::Vector3d(q[0], q[1], q[2]));
  }
  if (w.size() < 10) return std::nullopt;
  shapes::Region r = box_of(w, o.neck_share);
  if (r.height < o.min_height) return std::nullopt;
  r.transform(T.inverse());
  Segment seg(r);
  std::sort(pixels.begin(), pixels.end());
  seg.inliers = pixels.size();
  seg.pixels = std::move(pixels);
  detail::set_color(seg, color);
  return seg;
}

std::vector<std::vector<int>> object_regions(const Cloud& cloud, const extension::Mask& roi, const NormalMap* normals,
                                             double depth_jump, double max_grazing_deg, int min_pixels) {
  if (!roi.same_size(cloud)) throw InputError("object_regions: the mask's size differs from the cloud's");
  const FacesCamera faces(cloud, normals, max_grazing_deg);
  return connected_regions(cloud, depth_jump, min_pixels, [&](int i) { return roi.data()[i] != 0 && faces(i); });
}

}  // namespace mereo::features
