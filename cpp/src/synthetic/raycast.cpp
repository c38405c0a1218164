// Analytic ray-primitive intersections of the synthetic renderer.
#include "raycast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mereo::synthetic::detail {
namespace {

/// Roots of A t^2 + 2 B t + C = 0 in increasing order; false if none.
inline bool solve_quadratic(double A, double B, double C, double& t1, double& t2) {
  if (A <= 0) return false;
  const double disc = B * B - A * C;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  const double q = -(B + (B >= 0 ? sq : -sq));
  if (q == 0) {
    t1 = t2 = 0;
    return true;
  }
  t1 = q / A;
  t2 = C / q;
  if (t1 > t2) std::swap(t1, t2);
  return true;
}

bool hit_plane(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const double den = d.dot(p.a);
  if (std::abs(den) < 1e-14) return false;
  const double t = (p.c - o).dot(p.a) / den;
  if (!(t > tmin && t < tmax)) return false;
  h.t = t;
  h.n = p.a;
  return true;
}

bool hit_disc(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const double den = d.dot(p.a);
  if (std::abs(den) < 1e-14) return false;
  const Vec3 w = o - p.c;
  const double t = -w.dot(p.a) / den;
  if (!(t > tmin && t < tmax)) return false;
  Vec3 q = w + t * d;
  q -= q.dot(p.a) * p.a;
  const double r2 = q.squaredNorm();
  if (r2 > p.r * p.r || r2 < p.r_in * p.r_in) return false;
  h.t = t;
  h.n = p.a;
  return true;
}

bool hit_cylinder(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax,
                  Hit& h) {
  const Vec3 w = o - p.c;
  const double da = d.dot(p.a), wa = w.dot(p.a);
  const Vec3 dp = d - da * p.a, wp = w - wa * p.a;
  double t1, t2;
  if (!solve_quadratic(dp.squaredNorm(), dp.dot(wp), wp.squaredNorm() - p.r * p.r, t1, t2))
    return false;
  for (double t : {t1, t2}) {
    if (!(t > tmin && t < tmax)) continue;
    if (std::abs(wa + t * da) > p.half_h) continue;
    h.t = t;
    h.n = (wp + t * dp).normalized();
    return true;
  }
  return false;
}

/// A truncated cone about p.a: radius p.r + p.slope * s at s along the axis from p.c, |s| <=
/// half_h (the quadratic of |q - (q.a) a| = r + slope (q.a), on the nappe where that is > 0).
bool hit_cone(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const Vec3 w = o - p.c;
  const double da = d.dot(p.a), wa = w.dot(p.a), k = p.slope;
  const Vec3 dp = d - da * p.a, wp = w - wa * p.a;
  const double r0 = p.r + k * wa;
  double A = dp.squaredNorm() - k * k * da * da, B = dp.dot(wp) - k * da * r0, C = wp.squaredNorm() - r0 * r0;
  if (A < 0) A = -A, B = -B, C = -C;  // a ray steeper than the cone's side: the same roots
  double t1, t2;
  if (!solve_quadratic(A, B, C, t1, t2)) return false;
  for (double t : {t1, t2}) {
    if (!(t > tmin && t < tmax)) continue;
    const double s = wa + t * da;
    if (std::abs(s) > p.half_h || p.r + k * s <= 0) continue;
    h.t = t;
    h.n = ((wp + t * dp).normalized() - k * p.a).normalized();
    return true;
  }
  return false;
}

bool hit_sphere_zone(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax,
                     Hit& h) {
  const Vec3 w = o - p.c;
  double t1, t2;
  if (!solve_quadratic(1.0, w.dot(d), w.squaredNorm() - p.r * p.r, t1, t2)) return false;
  for (double t : {t1, t2}) {
    if (!(t > tmin && t < tmax)) continue;
    const Vec3 q = w + t * d;
    const double off = q.dot(p.a);
    if (off < p.hmin || off > p.hmax) continue;
    h.t = t;
    h.n = q.normalized();
    return true;
  }
  return false;
}

bool hit_box(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const Vec3 w = o - p.c;
  const Vec3 axes[3] = {p.b, p.e, p.a};
  double tn = -std::numeric_limits<double>::infinity();
  double tf = std::numeric_limits<double>::infinity();
  int in = -1, jf = -1;
  double sn = 0, sf = 0;
  for (int i = 0; i < 3; ++i) {
    const double ow = w.dot(axes[i]), dw = d.dot(axes[i]);
    const double hh = p.half[i];
    if (std::abs(dw) < 1e-15) {
      if (std::abs(ow) > hh) return false;
      continue;
    }
    double t0 = (-hh - ow) / dw, t1 = (hh - ow) / dw;
    // entering through the face at -hh when dw > 0 (outward normal -axis), else +hh
    double s0 = -1, s1 = 1;
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(s0, s1);
    }
    if (t0 > tn) {
      tn = t0;
      in = i;
      sn = s0;
    }
    if (t1 < tf) {
      tf = t1;
      jf = i;
      sf = s1;
    }
    if (tn > tf) return false;
  }
  if (in >= 0 && tn > tmin && tn < tmax) {
    h.t = tn;
    h.n = sn * axes[in];
    return true;
  }
  if (jf >= 0 && tf > tmin && tf < tmax) {
    h.t = tf;
    h.n = sf * axes[jf];
    return true;
  }
  return false;
}

/// The torus implicit function (centre at the origin, symmetry axis `a`) at q.
inline double torus_f(const Vec3& q, const Vec3& a, double R2, double r2) {
  const double q2 = q.squaredNorm();
  const double qa = q.dot(a);
  const double g = q2 + R2 - r2;
  return g * g - 4.0 * R2 * (q2 - qa * qa);
}

inline bool torus_accept(const Prim& p, const Vec3& q) {
  if (p.arc_len < kTwoPi) {
    double th = std::atan2(q.dot(p.e), q.dot(p.b)) - p.arc0;
    th = std::fmod(th, kTwoPi);
    if (th < 0) th += kTwoPi;
    if (th > p.arc_len) return false;
  }
  if (p.clip) {
    const Vec3 x = q + p.c - p.clip_c;
    const double xa = x.dot(p.clip_a);
    if (std::abs(xa) <= p.clip_half_h && (x - xa * p.clip_a).squaredNorm() < p.clip_r * p.clip_r)
      return false;
  }
  return true;
}

bool hit_torus(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const Vec3 w = o - p.c;
  const double rb = p.r + p.r_in;
  const double B = w.dot(d);
  const double C = w.squaredNorm() - rb * rb;
  const double disc = B * B - C;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  const double s0 = std::max(-B - sq, tmin);
  const double s1 = std::min(-B + sq, tmax);
  if (!(s0 < s1)) return false;
  const double R2 = p.r * p.r, r2 = p.r_in * p.r_in;
  auto f = [&](double t) { return torus_f(w + t * d, p.a, R2, r2); };
  const int n = std::max(1, int(std::ceil((s1 - s0) / kTorusStep)));
  const double step = (s1 - s0) / n;
  double ta = s0, fa = f(ta);
  for (int i = 1; i <= n; ++i) {
    const double tb = (i == n) ? s1 : s0 + i * step;
    const double fb = f(tb);
    if ((fa <= 0) != (fb <= 0)) {
      // bisection to ~1e-12 m
      double lo = ta, hi = tb, flo = fa;
      for (int k = 0; k < 40 && hi - lo > 1e-12; ++k) {
        const double mid = 0.5 * (lo + hi);
        const double fm = f(mid);
        if ((fm <= 0) == (flo <= 0)) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      const double t = 0.5 * (lo + hi);
      if (t > tmin && t < tmax) {
        const Vec3 q = w + t * d;
        if (torus_accept(p, q)) {
          const Vec3 qr = q - q.dot(p.a) * p.a;
          const double nr = qr.norm();
          const Vec3 ring = nr > 0 ? Vec3(qr * (p.r / nr)) : Vec3(p.b * p.r);
          h.t = t;
          h.n = (q - ring).normalized();
          return true;
        }
      }
    }
    ta = tb;
    fa = fb;
  }
  return false;
}

/// An ellipsoid: the unit sphere in its scaled local frame (the same ray parameter t).
bool hit_ellipsoid(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const Vec3 w = o - p.c;
  const Vec3 ol(w.dot(p.b) / p.half.x(), w.dot(p.e) / p.half.y(), w.dot(p.a) / p.half.z());
  const Vec3 dl(d.dot(p.b) / p.half.x(), d.dot(p.e) / p.half.y(), d.dot(p.a) / p.half.z());
  double t1, t2;
  if (!solve_quadratic(dl.squaredNorm(), ol.dot(dl), ol.squaredNorm() - 1.0, t1, t2)) return false;
  for (double t : {t1, t2}) {
    if (!(t > tmin && t < tmax)) continue;
    const Vec3 q = ol + t * dl;  // on the unit sphere; the gradient of |L^-1 x|^2 in the world
    h.t = t;
    h.n = (q.x() / p.half.x() * p.b + q.y() / p.half.y() * p.e + q.z() / p.half.z() * p.a).normalized();
    return true;
  }
  return false;
}

inline bool in_arc(const Prim& p, const Vec3& radial) {
  if (p.arc_len >= kTwoPi) return true;
  double th = std::atan2(radial.dot(p.e), radial.dot(p.b)) - p.arc0;
  th = std::fmod(th, kTwoPi);
  if (th < 0) th += kTwoPi;
  return th <= p.arc_len;
}

/// An annular sector of a cylinder: outer and inner lateral surfaces and the two flat caps.
bool hit_ring(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& h) {
  const Vec3 w = o - p.c;
  const double da = d.dot(p.a), wa = w.dot(p.a);
  const Vec3 dp = d - da * p.a, wp = w - wa * p.a;
  bool found = false;
  double best = tmax;
  for (const double radius : {p.r, p.r_in}) {
    double t1, t2;
    if (!solve_quadratic(dp.squaredNorm(), dp.dot(wp), wp.squaredNorm() - radius * radius, t1, t2)) continue;
    for (double t : {t1, t2}) {
      if (!(t > tmin && t < best)) continue;
      if (std::abs(wa + t * da) > p.half_h) continue;
      const Vec3 radial = wp + t * dp;
      if (!in_arc(p, radial)) continue;
      best = t;
      found = true;
      h.t = t;
      h.n = (radius == p.r ? 1.0 : -1.0) * radial.normalized();
    }
  }
  if (std::abs(da) > 1e-14) {
    for (const double side : {-1.0, 1.0}) {
      const double t = (side * p.half_h - wa) / da;
      if (!(t > tmin && t < best)) continue;
      const Vec3 radial = wp + t * dp;
      const double r2 = radial.squaredNorm();
      if (r2 > p.r * p.r || r2 < p.r_in * p.r_in || !in_arc(p, radial)) continue;
      best = t;
      found = true;
      h.t = t;
      h.n = side * p.a;
    }
  }
  return found;
}

inline bool inside_clip(const Prim& p, const Vec3& x) {
  const Vec3 w = x - p.clip_c;
  const double wa = w.dot(p.clip_a);
  return std::abs(wa) <= p.clip_half_h && (w - wa * p.clip_a).squaredNorm() < p.clip_r * p.clip_r;
}

bool intersect_surface(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& hit) {
  switch (p.kind) {
    case Kind::Plane: return hit_plane(p, o, d, tmin, tmax, hit);
    case Kind::Box: return hit_box(p, o, d, tmin, tmax, hit);
    case Kind::Cylinder: return hit_cylinder(p, o, d, tmin, tmax, hit);
    case Kind::Cone: return hit_cone(p, o, d, tmin, tmax, hit);
    case Kind::Disc: return hit_disc(p, o, d, tmin, tmax, hit);
    case Kind::SphereZone: return hit_sphere_zone(p, o, d, tmin, tmax, hit);
    case Kind::Torus: return hit_torus(p, o, d, tmin, tmax, hit);
    case Kind::Ellipsoid: return hit_ellipsoid(p, o, d, tmin, tmax, hit);
    case Kind::Ring: return hit_ring(p, o, d, tmin, tmax, hit);
  }
  return false;
}

}  // namespace

bool intersect(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& hit) {
  // a torus clips its own roots (hit_torus); the others: the next hit beyond a clipped one
  if (!p.clip || p.kind == Kind::Torus) return intersect_surface(p, o, d, tmin, tmax, hit);
  double from = tmin;
  for (int k = 0; k < 8; ++k) {
    if (!intersect_surface(p, o, d, from, tmax, hit)) return false;
    if (!inside_clip(p, o + hit.t * d)) return true;
    from = hit.t;
  }
  return false;
}

Bound bound_of(const Prim& p) {
  Bound b;
  switch (p.kind) {
    case Kind::Plane: b.r = -1; break;
    case Kind::Box: b.c = p.c; b.r = p.half.norm(); break;
    case Kind::Cylinder: b.c = p.c; b.r = std::hypot(p.r, p.half_h); break;
    case Kind::Cone: b.c = p.c; b.r = std::hypot(p.r + std::abs(p.slope) * p.half_h, p.half_h); break;
    case Kind::Disc: b.c = p.c; b.r = p.r; break;
    case Kind::SphereZone: b.c = p.c; b.r = p.r; break;
    case Kind::Torus: b.c = p.c; b.r = p.r + p.r_in; break;
    case Kind::Ellipsoid: b.c = p.c; b.r = p.half.maxCoeff(); break;
    case Kind::Ring: b.c = p.c; b.r = std::hypot(p.r, p.half_h); break;
  }
  return b;
}

bool cast_nearest(const RenderScene& rs, const Vec3& o, const Vec3& d, double tmin, double tmax,
                  RayHit& out) {
  double best = tmax;
  bool found = false;
  Hit h;
  for (std::size_t i = 0; i < rs.objects.size(); ++i) {
    const RenderObject& ro = rs.objects[i];
    if (!ray_hits_sphere(ro.bound, o, d, tmin, best)) continue;
    for (int k = ro.first; k < ro.first + ro.count; ++k) {
      if (intersect(rs.prims[k], o, d, tmin, best, h)) {
        best = h.t;
        found = true;
        out.t = h.t;
        out.n = h.n;
        out.label = rs.prims[k].label;
        out.object = rs.prims[k].object;
        out.obj_index = int(i);
      }
    }
  }
  return found;
}

void objects_hit(const RenderScene& rs, const Vec3& o, const Vec3& d, std::vector<std::uint32_t>& out,
                 std::vector<std::uint32_t>& parts) {
  out.clear(), parts.clear();
  Hit h;
  const double inf = std::numeric_limits<double>::infinity();
  for (const RenderObject& ro : rs.objects) {
    if (!ray_hits_sphere(ro.bound, o, d, 0.0, inf)) continue;
    bool any = false;
    for (int k = ro.first; k < ro.first + ro.count; ++k)
      if (intersect(rs.prims[k], o, d, 0.0, inf, h)) {
        any = true;
        if (std::find(parts.begin(), parts.end(), rs.prims[k].label) == parts.end()) parts.push_back(rs.prims[k].label);
      }
    if (any) out.push_back(rs.prims[std::size_t(ro.first)].object);
  }
}

bool cast_any(const RenderScene& rs, const Vec3& o, const Vec3& d, double tmin, double tmax) {
  Hit h;
  for (const RenderObject& ro : rs.objects) {
    if (!ray_hits_sphere(ro.bound, o, d, tmin, tmax)) continue;
    for (int k = ro.first; k < ro.first + ro.count; ++k)
      if (intersect(rs.prims[k], o, d, tmin, tmax, h)) return true;
  }
  return false;
}

}  // namespace mereo::synthetic::detail
