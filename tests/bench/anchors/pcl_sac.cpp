// Reference implementation: PCL 1.13 SACSegmentationFromNormals (RANSAC),
// applied repeatedly (fit, remove inliers, refit) to pull planes and cylinders
// out of a cloud. Used only by tests/bench/bench_primitives.cpp to compare
// mereo's detector against.
#include "anchors.hpp"

#include <pcl/ModelCoefficients.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <iterator>
#include <memory>
#include <numeric>

namespace mereo::bench {

namespace {

constexpr int kMaxExtractions = 20;  // per model type
constexpr int kMaxIterations = 1000;
constexpr double kNormalDistanceWeight = 0.1;

using Seg = pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal>;

// Repeatedly fits `seg`'s model to the points listed in `remaining` (indices
// into the full cloud), removing each accepted model's inliers from
// `remaining` (which is updated in place). Stops when a fit has fewer than
// min_points inliers.
// `make` turns the model coefficients (and inliers) into an AnchorShape.
template <class Make>
void extract_repeatedly(Seg& seg, pcl::IndicesPtr& remaining, int min_points, Make make,
                        std::vector<AnchorShape>& out) {
  for (int k = 0; k < kMaxExtractions; ++k) {
    if (static_cast<int>(remaining->size()) < std::max(min_points, 3)) break;
    // Working on an index subset of the full cloud means the returned inliers
    // are already indices into the input arrays (no re-mapping needed).
    seg.setIndices(remaining);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coeffs;
    seg.segment(inliers, coeffs);
    if (static_cast<int>(inliers.indices.size()) < min_points) break;

    AnchorShape a = make(coeffs.values, inliers.indices);
    a.indices.assign(inliers.indices.begin(), inliers.indices.end());
    std::sort(a.indices.begin(), a.indices.end());

    // remaining := remaining \ inliers (both sorted). A fresh vector is used
    // because `seg` still holds a pointer to the old one.
    auto next = std::make_shared<pcl::Indices>();
    next->reserve(remaining->size() - a.indices.size());
    std::set_difference(remaining->begin(), remaining->end(), a.indices.begin(), a.indices.end(),
                        std::back_inserter(*next));
    remaining = next;
    out.push_back(std::move(a));
  }
}

}  // namespace

std::vector<AnchorShape> pcl_sac_cylinders(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<Eigen::Vector3f>& normals,
                                           const AnchorOptions& o) {
  std::vector<AnchorShape> out;
  const size_t n = std::min(points.size(), normals.size());
  if (n == 0) return out;

  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  auto cloud_normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  cloud->resize(n);
  cloud_normals->resize(n);
  for (size_t i = 0; i < n; ++i) {
    (*cloud)[i] = pcl::PointXYZ(points[i].x(), points[i].y(), points[i].z());
    (*cloud_normals)[i] = pcl::Normal(normals[i].x(), normals[i].y(), normals[i].z());
  }

  // Shared, sorted list of not-yet-explained points (indices into the input).
  auto remaining = std::make_shared<pcl::Indices>(n);
  std::iota(remaining->begin(), remaining->end(), 0);

  // PCL seeds its samplers with a fixed value (12345) unless asked not to, so
  // runs are deterministic.
  Seg seg;
  seg.setInputCloud(cloud);
  seg.setInputNormals(cloud_normals);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setOptimizeCoefficients(true);
  seg.setNormalDistanceWeight(kNormalDistanceWeight);
  seg.setMaxIterations(kMaxIterations);
  seg.setDistanceThreshold(o.epsilon);

  if (o.plane) {
    // Coefficients: normalised (a, b, c, d) with a x + b y + c z + d = 0.
    seg.setModelType(pcl::SACMODEL_NORMAL_PLANE);
    auto make_plane = [&](const std::vector<float>& c, const pcl::Indices& inl) {
      AnchorShape a;
      a.cls = "plane";
      Eigen::Vector3d nrm(c[0], c[1], c[2]);
      const double len = nrm.norm();
      a.axis = nrm / len;
      // A point on the plane: the projection of the first inlier.
      const Eigen::Vector3d p0 = points[inl.front()].cast<double>();
      a.point = p0 - (a.axis.dot(p0) + c[3] / len) * a.axis;
      return a;
    };
    extract_repeatedly(seg, remaining, o.min_points, make_plane, out);
  }

  if (o.cylinder) {
    // Coefficients: point on axis (3), axis direction (3), radius.
    seg.setModelType(pcl::SACMODEL_CYLINDER);
    seg.setRadiusLimits(o.min_radius, o.max_radius);
    auto make_cylinder = [](const std::vector<float>& c, const pcl::Indices&) {
      AnchorShape a;
      a.cls = "cylinder";
      a.point = Eigen::Vector3d(c[0], c[1], c[2]);
      a.axis = Eigen::Vector3d(c[3], c[4], c[5]).normalized();
      a.radius = c[6];
      return a;
    };
    extract_repeatedly(seg, remaining, o.min_points, make_cylinder, out);
  }
  return out;
}

}  // namespace mereo::bench
