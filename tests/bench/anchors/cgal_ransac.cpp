// Reference implementation: CGAL 5.5 Efficient RANSAC (Schnabel et al. 2007)
// wrapped for the primitive benchmark. Used only by
// tests/bench/bench_primitives.cpp to compare mereo's detector against.
#include "anchors.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

namespace mereo::bench {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
// Efficient_RANSAC shuffles its input range in place (preprocessing), and a
// shape's indices_of_assigned_points() refer to that shuffled range. So each
// point carries its original index as a third tuple element.
using PointWithNormal = std::tuple<Point, Vector, int>;
using PwnVector = std::vector<PointWithNormal>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, PointWithNormal>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, PointWithNormal>;
using Traits =
    CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PwnVector, PointMap, NormalMap>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;
using Plane = CGAL::Shape_detection::Plane<Traits>;
using Cylinder = CGAL::Shape_detection::Cylinder<Traits>;
using Sphere = CGAL::Shape_detection::Sphere<Traits>;
using Torus = CGAL::Shape_detection::Torus<Traits>;

Eigen::Vector3d to_eigen(const Point& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d to_eigen(const Vector& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<AnchorShape> cgal_efficient_ransac(const std::vector<Eigen::Vector3f>& points,
                                               const std::vector<Eigen::Vector3f>& normals,
                                               const AnchorOptions& o, unsigned seed) {
  std::vector<AnchorShape> out;
  const size_t n = std::min(points.size(), normals.size());
  if (n == 0) return out;

  PwnVector pwn;
  pwn.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& p = points[i];
    const auto& q = normals[i];
    pwn.emplace_back(Point(p.x(), p.y(), p.z()), Vector(q.x(), q.y(), q.z()),
                     static_cast<int>(i));
  }

  // All of Efficient_RANSAC's sampling goes through CGAL's (thread-local)
  // default generator; reseeding it makes a run reproducible.
  CGAL::get_default_random() = CGAL::Random(seed);

  Ransac ransac;
  ransac.set_input(pwn);
  if (o.plane) ransac.add_shape_factory<Plane>();
  if (o.cylinder) ransac.add_shape_factory<Cylinder>();
  if (o.sphere) ransac.add_shape_factory<Sphere>();
  if (o.torus) ransac.add_shape_factory<Torus>();

  Ransac::Parameters params;
  params.probability = o.probability;
  params.min_points = static_cast<std::size_t>(std::max(1, o.min_points));
  params.epsilon = o.epsilon;
  params.cluster_epsilon = o.cluster_epsilon;
  params.normal_threshold = std::cos(o.normal_deviation_deg * M_PI / 180.0);
  ransac.detect(params);

  for (const auto& shape : ransac.shapes()) {
    AnchorShape a;
    // Map positions in the (shuffled) range back to input indices.
    for (std::size_t k : shape->indices_of_assigned_points())
      a.indices.push_back(std::get<2>(pwn[k]));
    std::sort(a.indices.begin(), a.indices.end());

    if (const auto* pl = dynamic_cast<const Plane*>(shape.get())) {
      a.cls = "plane";
      Eigen::Vector3d nrm = to_eigen(pl->plane_normal());
      const double len = nrm.norm();
      nrm /= len;
      const double d = pl->d() / len;  // plane: nrm . x + d = 0
      // A point on the plane: the projection of the first inlier.
      Eigen::Vector3d p0 = a.indices.empty() ? Eigen::Vector3d(-d * nrm)
                                             : points[a.indices[0]].cast<double>();
      a.point = p0 - (nrm.dot(p0) + d) * nrm;
      a.axis = nrm;
    } else if (const auto* cy = dynamic_cast<const Cylinder*>(shape.get())) {
      a.cls = "cylinder";
      const auto line = cy->axis();
      a.point = to_eigen(line.point(0));
      a.axis = to_eigen(line.to_vector()).normalized();
      a.radius = cy->radius();
    } else if (const auto* sp = dynamic_cast<const Sphere*>(shape.get())) {
      a.cls = "sphere";
      a.point = to_eigen(sp->center());
      a.radius = sp->radius();
    } else if (const auto* to = dynamic_cast<const Torus*>(shape.get())) {
      a.cls = "torus";
      a.point = to_eigen(to->center());
      a.axis = to_eigen(to->axis()).normalized();
      a.radius = to->major_radius();
      a.minor_radius = to->minor_radius();
    } else {
      continue;  // no other factories are registered
    }
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace mereo::bench
