// The renderer's primitives of a Shape: one for most classes, several for the composite ones
// (a rounded box, a loop or a band swept along a rounded rectangle), each piece exact.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mereo/synthetic/scene.hpp"
#include "raycast.hpp"

namespace mereo::synthetic::detail {
namespace {

constexpr double kHalfPi = 1.5707963267948966192313216916398;

/// `axis2` made orthogonal to the unit axis a.
Vec3 reference(const Shape& s, const Vec3& a) { return (s.axis2 - s.axis2.dot(a) * a).normalized(); }

Prim box_prim(const Vec3& c, const Vec3& x, const Vec3& z, const Vec3& half) {
  Prim p;
  p.kind = Kind::Box;
  p.c = c;
  p.a = z;
  p.b = x;
  p.e = z.cross(x);
  p.half = half;
  return p;
}

Prim cylinder_prim(const Vec3& c, const Vec3& axis, double r, double half_h) {
  Prim p;
  p.kind = Kind::Cylinder;
  p.c = c;
  p.a = axis;
  p.r = r;
  p.half_h = half_h;
  return p;
}

Prim sphere_prim(const Vec3& c, double r) {
  Prim p;
  p.kind = Kind::SphereZone;
  p.c = c;
  p.r = r;
  p.hmin = -r;
  p.hmax = r;
  return p;
}

/// A rounded box: the points within `radius` of the inner box (the outer extents less the
/// rounding), as the union of three boxes (the inner one grown along each axis), twelve edge
/// cylinders and eight corner spheres. Seen from outside, the nearest surface of a union of
/// convex pieces is the union's.
void rounded_box(const Shape& s, std::vector<Prim>& out) {
  const Vec3 z = s.axis.normalized(), x = reference(s, z), y = z.cross(x);
  const Vec3 axes[3] = {x, y, z};
  const double rho = s.radius;
  Vec3 h = 0.5 * s.size - Vec3::Constant(rho);
  h = h.cwiseMax(0.0);
  for (int i = 0; i < 3; ++i) {
    Vec3 half = h;
    half[i] += rho;
    if (half.minCoeff() > 0) out.push_back(box_prim(s.point, x, z, half));
  }
  for (int i = 0; i < 3; ++i) {
    if (h[i] <= 0) continue;
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    for (const double sj : {-1.0, 1.0})
      for (const double sk : {-1.0, 1.0})
        out.push_back(cylinder_prim(s.point + sj * h[j] * axes[j] + sk * h[k] * axes[k], axes[i], rho, h[i]));
  }
  for (const double sx : {-1.0, 1.0})
    for (const double sy : {-1.0, 1.0})
      for (const double sz : {-1.0, 1.0})
        out.push_back(sphere_prim(s.point + sx * h.x() * x + sy * h.y() * y + sz * h.z() * z, rho));
}

/// A tube ("loop") or a flat strip ("band") along a rounded rectangle: four quarter corners
/// (torus arcs, or annular sectors of a cylinder) and the straight sides between them
/// (cylinders, or boxes). The pieces meet at the planes normal to the centre line.
void swept(const Shape& s, std::vector<Prim>& out) {
  const bool band = s.cls == "band";
  const Vec3 n = s.axis.normalized(), X = reference(s, n), Y = n.cross(X);
  const double hx = 0.5 * s.size.x(), hy = 0.5 * s.size.y(), rc = s.radius, t = s.minor_radius;
  if (!(t > 0) || !(rc > t) || rc > hx + 1e-12 || rc > hy + 1e-12)
    throw std::invalid_argument("synthetic: a " + s.cls + " needs 0 < minor_radius < radius <= half of each extent");
  const double cx = std::max(0.0, hx - rc), cy = std::max(0.0, hy - rc);  // corner centres
  for (const auto& [sx, sy] : {std::pair{1.0, 1.0}, {-1.0, 1.0}, {-1.0, -1.0}, {1.0, -1.0}}) {
    Prim p;
    p.c = s.point + sx * cx * X + sy * cy * Y;
    p.b = sx * X;  // the arc from the side along Y (at +-hx) to the side along X (at +-hy)
    p.e = sy * Y;
    p.a = p.b.cross(p.e);  // so that a x b = e: angles run from b towards e
    p.arc0 = 0.0;
    p.arc_len = kHalfPi;
    if (band) {
      p.kind = Kind::Ring;
      p.r = rc + t;
      p.r_in = rc - t;
      p.half_h = 0.5 * s.height;
    } else {
      p.kind = Kind::Torus;
      p.r = rc;
      p.r_in = t;
    }
    out.push_back(p);
  }
  for (const double side : {-1.0, 1.0}) {
    if (cx > 0) {  // the sides along X, at y = +-hy
      const Vec3 c = s.point + side * hy * Y;
      out.push_back(band ? box_prim(c, X, n, Vec3(cx, t, 0.5 * s.height)) : cylinder_prim(c, X, t, cx));
    }
    if (cy > 0) {  // the sides along Y, at x = +-hx
      const Vec3 c = s.point + side * hx * X;
      out.push_back(band ? box_prim(c, Y, n, Vec3(cy, t, 0.5 * s.height)) : cylinder_prim(c, Y, t, cy));
    }
  }
}

}  // namespace

void append_prims(const Shape& s, std::vector<Prim>& out) {
  if (s.cls == "rounded_box") return rounded_box(s, out);
  if (s.cls == "loop" || s.cls == "band") return swept(s, out);
  Prim p;
  p.c = s.point;
  p.a = s.axis.normalized();
  if (s.cls == "plane") {
    p.kind = Kind::Plane;
  } else if (s.cls == "box") {
    p.kind = Kind::Box;
    p.b = reference(s, p.a);
    p.e = p.a.cross(p.b);
    p.half = 0.5 * s.size;
  } else if (s.cls == "ellipsoid") {
    p.kind = Kind::Ellipsoid;
    p.b = reference(s, p.a);
    p.e = p.a.cross(p.b);
    p.half = 0.5 * s.size;
  } else if (s.cls == "cylinder") {
    p.kind = Kind::Cylinder;
    p.r = s.radius;
    p.half_h = 0.5 * s.height;
  } else if (s.cls == "cone") {
    p.kind = Kind::Cone;
    p.r = s.radius;
    p.half_h = 0.5 * s.height;
    p.slope = std::tan(s.angle);
  } else if (s.cls == "disc") {
    p.kind = Kind::Disc;
    p.r = s.radius;
    p.r_in = s.minor_radius;
  } else if (s.cls == "sphere") {
    p.kind = Kind::SphereZone;
    p.r = s.radius;
    p.hmin = s.height_min;
    p.hmax = s.height_max;
  } else if (s.cls == "torus") {
    p.kind = Kind::Torus;
    p.b = reference(s, p.a);
    p.e = p.a.cross(p.b);
    p.r = s.radius;
    p.r_in = s.minor_radius;
    if (s.arc_end > s.arc_start) {
      p.arc0 = s.arc_start;
      p.arc_len = s.arc_end - s.arc_start;
    } else {
      p.arc0 = 0;
      p.arc_len = kTwoPi;
    }
  } else {
    throw std::invalid_argument("synthetic: unknown shape class '" + s.cls + "'");
  }
  out.push_back(p);
}

}  // namespace mereo::synthetic::detail
