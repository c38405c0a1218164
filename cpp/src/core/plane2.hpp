// Coordinates in a plane seen from above (the support's): `up` normalized and an orthonormal pair
// e1, e2 across it, so that a point's footprint is of(x). Used where bodies stand on the support:
// the upright-body search (features/upright.cpp) and the scene relations (cognitive/relations.cpp).
#pragma once

#include <Eigen/Geometry>

namespace mereo::detail {

struct Plane2 {
  Eigen::Vector3d up, e1, e2;
  explicit Plane2(const Eigen::Vector3d& u) : up(u.normalized()) {
    e1 = up.unitOrthogonal();
    e2 = up.cross(e1);
  }
  Eigen::Vector2d of(const Eigen::Vector3d& x) const { return {e1.dot(x), e2.dot(x)}; }
};

}  // namespace mereo::detail
