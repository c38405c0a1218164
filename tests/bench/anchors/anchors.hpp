// Reference ("anchor") primitive detectors: thin adapters that run CGAL's
// Efficient RANSAC and PCL's SAC segmentation on the same points and normals as
// mereo's detector. Used only by tests/bench/bench_primitives.cpp to compare
// against; not part of the library. This header deliberately pulls in no
// CGAL/PCL headers so that the benchmark itself stays free of them.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace mereo::bench {

/// One primitive found by a reference detector.
struct AnchorShape {
  std::string cls;  // "plane", "cylinder", "sphere", "torus"
  // plane: a point on it; cylinder: a point on the axis; sphere/torus: centre
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  // plane normal / cylinder axis / torus ring-plane normal (unit)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double radius = 0, minor_radius = 0;  // cylinder/sphere radius; torus major + minor radius
  std::vector<int> indices;             // indices into the input arrays of the shape's inliers
};

/// Shared settings for the reference detectors.
struct AnchorOptions {
  double epsilon = 0.006;          // max point distance, metres
  double cluster_epsilon = 0.01;   // connectivity (CGAL cluster_epsilon), metres
  double normal_deviation_deg = 25;
  int min_points = 250;
  double probability = 0.05;       // CGAL
  bool plane = true, cylinder = true, sphere = true, torus = true;
  double min_radius = 0.01, max_radius = 0.35;  // PCL cylinder radius limits
};

/// CGAL 5.5 Shape_detection Efficient_RANSAC (planes, cylinders, spheres, tori
/// as enabled) on points+normals. CGAL's global random generator is reseeded
/// from `seed`, so results are reproducible for a given input and seed.
std::vector<AnchorShape> cgal_efficient_ransac(const std::vector<Eigen::Vector3f>& points,
                                               const std::vector<Eigen::Vector3f>& normals,
                                               const AnchorOptions& o, unsigned seed = 0);

/// PCL 1.13 SACSegmentationFromNormals with RANSAC: when o.plane is set, planes
/// (SACMODEL_NORMAL_PLANE) are extracted first, then cylinders
/// (SACMODEL_CYLINDER); each model is fitted, its inliers removed, and this is
/// repeated while the model has >= o.min_points inliers (at most 20 times per
/// model). Distance threshold o.epsilon, normal distance weight 0.1, cylinder
/// radius limits [o.min_radius, o.max_radius], 1000 iterations.
std::vector<AnchorShape> pcl_sac_cylinders(const std::vector<Eigen::Vector3f>& points,
                                           const std::vector<Eigen::Vector3f>& normals,
                                           const AnchorOptions& o);

}  // namespace mereo::bench
