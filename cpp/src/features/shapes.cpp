// Distances, minimal sets and least-squares refits of planes, spheres, cylinders and tori.
#include "features/shapes.hpp"

#include <cmath>
#include <functional>

#include <Eigen/Dense>

namespace mereo::features::detail {

double signed_distance(const Segment& s, const Eigen::Vector3d& x, Eigen::Vector3d* normal) {
  switch (s.cls) {
    case PrimitiveClass::Plane: {
      if (normal) *normal = s.axis;
      return s.axis.dot(x) + s.d;
    }
    case PrimitiveClass::Sphere: {
      const Eigen::Vector3d q = x - s.point;
      const double l = q.norm();
      if (normal) *normal = l > 0 ? Eigen::Vector3d(q / l) : Eigen::Vector3d::UnitZ();
      return l - s.radius;
    }
    case PrimitiveClass::Cylinder: {
      const Eigen::Vector3d q = x - s.point;
      const Eigen::Vector3d radial = q - s.axis * s.axis.dot(q);
      const double l = radial.norm();
      if (normal) *normal = l > 0 ? Eigen::Vector3d(radial / l) : Eigen::Vector3d::UnitX();
      return l - s.radius;
    }
    case PrimitiveClass::Torus: {
      const Eigen::Vector3d q = x - s.point;
      const Eigen::Vector3d inplane = q - s.axis * s.axis.dot(q);
      const double rho = inplane.norm();
      const Eigen::Vector3d ring = rho > 0 ? Eigen::Vector3d(inplane / rho * s.radius) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d t = q - ring;
      const double l = t.norm();
      if (normal) *normal = l > 0 ? Eigen::Vector3d(t / l) : s.axis;
      return l - s.minor_radius;
    }
    default:
      if (normal) *normal = Eigen::Vector3d::UnitZ();
      return INFINITY;
  }
}

std::optional<Segment> plane_from(const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  Segment s;
  s.cls = PrimitiveClass::Plane;
  s.axis = n.normalized();
  s.d = -s.axis.dot(p);
  s.point = p;
  return s;
}

std::optional<Segment> sphere_from(const Eigen::Vector3d& p1, const Eigen::Vector3d& n1, const Eigen::Vector3d& p2,
                                   const Eigen::Vector3d& n2) {
  // closest points of the lines p1 + t n1 and p2 + u n2
  const Eigen::Vector3d w = p1 - p2;
  const double a = n1.dot(n1), b = n1.dot(n2), c = n2.dot(n2), d = n1.dot(w), e = n2.dot(w);
  const double den = a * c - b * b;
  if (std::abs(den) < 1e-6) return std::nullopt;
  const double t = (b * e - c * d) / den, u = (a * e - b * d) / den;
  const Eigen::Vector3d c1 = p1 + t * n1, c2 = p2 + u * n2;
  if ((c1 - c2).norm() > 0.25 * (std::abs(t) + std::abs(u)) + 1e-3) return std::nullopt;  // normals miss
  Segment s;
  s.cls = PrimitiveClass::Sphere;
  s.point = 0.5 * (c1 + c2);
  s.radius = 0.5 * ((p1 - s.point).norm() + (p2 - s.point).norm());
  return s;
}

std::optional<Segment> cylinder_from(const Eigen::Vector3d& p1, const Eigen::Vector3d& n1, const Eigen::Vector3d& p2,
                                     const Eigen::Vector3d& n2) {
  Eigen::Vector3d axis = n1.cross(n2);
  const double sn = axis.norm();
  if (sn < 0.05) return std::nullopt;  // nearly parallel normals: no axis
  axis /= sn;
  // in the plane orthogonal to the axis, the normal lines meet at the axis
  const Eigen::Vector3d m1 = n1 - axis * axis.dot(n1), m2 = n2 - axis * axis.dot(n2);
  const Eigen::Vector3d q1 = p1 - axis * axis.dot(p1), q2 = p2 - axis * axis.dot(p2);
  const Eigen::Vector3d w = q1 - q2;
  const double a = m1.dot(m1), b = m1.dot(m2), c = m2.dot(m2), d = m1.dot(w), e = m2.dot(w);
  const double den = a * c - b * b;
  if (std::abs(den) < 1e-9) return std::nullopt;
  const double t = (b * e - c * d) / den, u = (a * e - b * d) / den;
  const Eigen::Vector3d c1 = q1 + t * m1, c2 = q2 + u * m2;
  Segment s;
  s.cls = PrimitiveClass::Cylinder;
  s.axis = axis;
  s.point = 0.5 * (c1 + c2) + axis * axis.dot(p1);
  s.radius = 0.5 * ((q1 - c1).norm() + (q2 - c2).norm());
  return s;
}

std::optional<Segment> torus_from(const Eigen::Vector3d* p, const Eigen::Vector3d* n, double min_minor,
                                  double max_minor) {
  // det[q2 - q1, q3 - q1, q4 - q1] with q_i = p_i - r n_i: a cubic in r; its root in range by
  // sampling and bisection
  auto det = [&](double r) {
    const Eigen::Vector3d q1 = p[0] - r * n[0];
    Eigen::Matrix3d M;
    M.col(0) = p[1] - r * n[1] - q1;
    M.col(1) = p[2] - r * n[2] - q1;
    M.col(2) = p[3] - r * n[3] - q1;
    return M.determinant();
  };
  const int steps = 24;
  double best_r = -1;
  double prev = det(min_minor);
  for (int i = 1; i <= steps && best_r < 0; ++i) {
    double lo = min_minor + (max_minor - min_minor) * (i - 1) / steps, hi = min_minor + (max_minor - min_minor) * i / steps;
    const double cur = det(hi);
    if (prev == 0) best_r = lo;
    else if (prev * cur < 0) {
      double flo = prev;
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi), fm = det(mid);
        if (flo * fm <= 0) hi = mid;
        else lo = mid, flo = fm;
      }
      best_r = 0.5 * (lo + hi);
    }
    prev = cur;
  }
  if (best_r < 0) return std::nullopt;
  // the ring: the circle through q1, q2, q3
  const Eigen::Vector3d a = p[0] - best_r * n[0], b = p[1] - best_r * n[1], c = p[2] - best_r * n[2];
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const Eigen::Vector3d nn = ab.cross(ac);
  const double l2 = nn.squaredNorm();
  if (l2 < 1e-14) return std::nullopt;
  const Eigen::Vector3d centre = a + (ac.squaredNorm() * nn.cross(ab) + ab.squaredNorm() * ac.cross(nn)) / (2 * l2);
  Segment s;
  s.cls = PrimitiveClass::Torus;
  s.point = centre;
  s.axis = nn / std::sqrt(l2);
  s.radius = (a - centre).norm();
  s.minor_radius = best_r;
  // the fourth tube centre must lie on the ring too
  const Eigen::Vector3d d = p[3] - best_r * n[3];
  if (std::abs((d - centre).norm() - s.radius) > 0.1 * s.radius + 0.002) return std::nullopt;
  return s;
}

namespace {

// parameters <-> segment, for LM
Eigen::VectorXd pack(const Segment& s) {
  switch (s.cls) {
    case PrimitiveClass::Sphere: {
      Eigen::VectorXd v(4);
      v << s.point, s.radius;
      return v;
    }
    case PrimitiveClass::Cylinder: {
      Eigen::VectorXd v(7);
      v << s.point, s.axis, s.radius;
      return v;
    }
    case PrimitiveClass::Torus: {
      Eigen::VectorXd v(8);
      v << s.point, s.axis, s.radius, s.minor_radius;
      return v;
    }
    default: return Eigen::VectorXd();
  }
}
Segment unpack(const Segment& like, const Eigen::VectorXd& v) {
  Segment s = like;
  s.point = v.head<3>();
  if (s.cls == PrimitiveClass::Sphere) {
    s.radius = v(3);
  } else {
    s.axis = v.segment<3>(3).normalized();
    s.radius = v(6);
    if (s.cls == PrimitiveClass::Torus) s.minor_radius = v(7);
  }
  return s;
}

/// A least-squares fit of a few parameters gains nothing from thousands of points but time.
constexpr std::size_t kFitPoints = 600;

/// Levenberg-Marquardt on the residuals f(x) (N of them), numerical Jacobian; x is updated.
void levenberg_marquardt(Eigen::VectorXd& x, int N, const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& f) {
  const int P = int(x.size());
  Eigen::VectorXd r(N), r2(N);
  f(x, r);
  double cost = r.squaredNorm(), lambda = 1e-3;
  Eigen::MatrixXd J(N, P);
  for (int it = 0; it < 30; ++it) {
    for (int k = 0; k < P; ++k) {
      Eigen::VectorXd xp = x;
      const double h = 1e-6 * std::max(1.0, std::abs(x(k)));
      xp(k) += h;
      f(xp, r2);
      J.col(k) = (r2 - r) / h;
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 8 && !improved; ++tries) {
      Eigen::MatrixXd Ad = A;
      Ad.diagonal() *= (1 + lambda);
      const Eigen::VectorXd step = Ad.ldlt().solve(-g);
      const Eigen::VectorXd xn = x + step;
      f(xn, r2);
      const double c2 = r2.squaredNorm();
      if (std::isfinite(c2) && c2 < cost) {
        x = xn, r = r2, lambda *= 0.3;
        improved = cost - c2 > 1e-14 * cost;
        cost = c2;
        if (!improved) break;
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
}

void set_residual(Segment& s, const std::vector<Eigen::Vector3d>& points) {
  double ss = 0;
  for (const auto& p : points) {
    const double d = signed_distance(s, p);
    ss += d * d;
  }
  s.residual = points.empty() ? 0.0 : std::sqrt(ss / double(points.size()));
}

}  // namespace

const std::vector<Eigen::Vector3d>& subsample_into(const std::vector<Eigen::Vector3d>& points,
                                                   std::vector<Eigen::Vector3d>& buffer, std::size_t max_points) {
  if (points.size() <= max_points) return points;
  buffer.clear();
  const double stride = double(points.size()) / double(max_points);
  for (std::size_t k = 0; k < max_points; ++k) buffer.push_back(points[std::size_t(k * stride)]);
  return buffer;
}

double range_residual(const Segment& s, const Eigen::Vector3d& x) {
  if (s.cls != PrimitiveClass::Cylinder && s.cls != PrimitiveClass::Sphere) return signed_distance(s, x);
  const double range = x.norm();
  if (!(range > 0)) return signed_distance(s, x);
  const Eigen::Vector3d d = x / range;
  // across the axis (a sphere: all of it): the ray t*w against the circle of centre c, radius r
  Eigen::Vector3d w = d, c = s.point;
  if (s.cls == PrimitiveClass::Cylinder) w -= s.axis * s.axis.dot(d), c -= s.axis * s.axis.dot(s.point);
  const double ww = w.squaredNorm(), wc = w.dot(c);
  const double disc = wc * wc - ww * (c.squaredNorm() - s.radius * s.radius);  // (r cos(incidence))^2 * ww
  // Grazing rays (incidence past ~80 degrees, or a miss): the range is ill-defined there; the
  // distance along the normal, turned into range at that incidence, continues it.
  constexpr double kMinCos = 0.17;
  const double cos_in = disc > 0 && ww > 0 ? std::sqrt(disc / ww) / s.radius : 0.0;
  if (cos_in < kMinCos || ww < 1e-12) return signed_distance(s, x) / (kMinCos * std::sqrt(std::max(ww, 1e-12)));
  // the crossing nearer the point: the near one on an outer wall, the far one on an inner wall
  // (beyond the near crossing is inside the shape, beyond the far one outside: signed_distance's
  // sign)
  const double near = (wc - std::sqrt(disc)) / ww, far = (wc + std::sqrt(disc)) / ww;
  return std::abs(range - near) <= std::abs(range - far) ? near - range : range - far;
}

Segment refit_points(const Segment& s0, const std::vector<Eigen::Vector3d>& points, Residual residual) {
  Segment s = s0;
  if (points.size() < 4) return s;
  if (s.cls == PrimitiveClass::Plane) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : points) c += p;
    c /= double(points.size());
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& p : points) C += (p - c) * (p - c).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    Eigen::Vector3d n = es.eigenvectors().col(0);
    if (n.dot(s0.axis) < 0) n = -n;
    s.axis = n, s.d = -n.dot(c), s.point = c;
  } else {
    Eigen::VectorXd x = pack(s);
    std::vector<Eigen::Vector3d> buffer;
    const auto& pts = subsample_into(points, buffer, kFitPoints);
    const int N = int(pts.size());
    levenberg_marquardt(x, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
      const Segment t = unpack(s0, v);
      if (residual == Residual::AlongRay)
        for (int i = 0; i < N; ++i) r(i) = range_residual(t, pts[i]);
      else
        for (int i = 0; i < N; ++i) r(i) = signed_distance(t, pts[i]);
    });
    s = unpack(s0, x);
  }
  set_residual(s, points);
  return s;
}

namespace {
/// A handle's torus from (azimuth, height, distance from the axis, ring radius, tube radius)
/// about `body`: the ring plane holds the body's axis.
Segment handle_torus(const Segment& body, const Eigen::VectorXd& v) {
  const Eigen::Vector3d a = body.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const Eigen::Vector3d u = std::cos(v(0)) * e1 + std::sin(v(0)) * e2;
  Segment t;
  t.cls = PrimitiveClass::Torus;
  t.point = body.point + a * v(1) + u * v(2);
  t.axis = a.cross(u).normalized();
  t.radius = v(3);
  t.minor_radius = v(4);
  if (v.size() > 5) t.axis = Eigen::AngleAxisd(v(5), a) * t.axis;  // the ring plane turned about the axis
  return t;
}

/// The handle fit's residuals: a point is seen on the side of the tube that faces the camera;
/// one that the fit would put on the far side costs up to a tube's diameter more (a thin tube
/// can otherwise be fitted in front of the points as well as behind them).
void handle_residuals(const Segment& t, const std::vector<Eigen::Vector3d>& pts, Eigen::VectorXd& r) {
  for (int i = 0; i < int(pts.size()); ++i) {
    Eigen::Vector3d sn;
    const double d = signed_distance(t, pts[std::size_t(i)], &sn);
    const double away = -sn.dot(-pts[std::size_t(i)].normalized());
    r(i) = d + 2 * t.minor_radius * std::max(0.0, away);
  }
}

/// (azimuth, height, distance from the axis, ring radius, tube radius) of a torus about `body`.
Eigen::VectorXd handle_params(const Segment& body, const Segment& t) {
  const Eigen::Vector3d a = body.axis.normalized(), e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  const Eigen::Vector3d q = t.point - body.point;
  const double h = a.dot(q);
  const Eigen::Vector3d radial = q - a * h;
  Eigen::VectorXd x(5);
  x << std::atan2(radial.dot(e2), radial.dot(e1)), h, radial.norm(), t.radius, t.minor_radius;
  return x;
}
}  // namespace

HandleTurn handle_turn(const Segment& body, const Segment& t, const std::vector<Eigen::Vector3d>& points) {
  HandleTurn out;
  if (points.size() < 6) return out;
  std::vector<Eigen::Vector3d> buffer;
  const auto& pts = subsample_into(points, buffer, kFitPoints);
  const int N = int(pts.size());
  const Eigen::VectorXd x0 = handle_params(body, t);
  Eigen::VectorXd r(N);
  handle_residuals(t, pts, r);
  out.rms_held = std::sqrt(r.squaredNorm() / N);
  out.rms_turned = out.rms_held;
  // the ring and its turn, the tube held; from no turn and from a turn either way (a local fit)
  for (double start : {0.0, 40.0, -40.0}) {
    Eigen::VectorXd y(5);
    y << x0.head<4>(), start * M_PI / 180.0;
    levenberg_marquardt(y, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& res) {
      Eigen::VectorXd full(6);
      full << v.head<4>(), x0(4), v(4);
      handle_residuals(handle_torus(body, full), pts, res);
    });
    Eigen::VectorXd full(6);
    full << y.head<4>(), x0(4), y(4);
    handle_residuals(handle_torus(body, full), pts, r);
    const double rms = std::sqrt(r.squaredNorm() / N);
    if (rms < out.rms_turned) out.rms_turned = rms, out.turn_deg = std::remainder(y(4), M_PI) * 180.0 / M_PI;
  }
  return out;
}

Segment refit_handle(const Segment& body, const Segment& t0, const std::vector<Eigen::Vector3d>& points,
                     bool fix_minor) {
  Eigen::VectorXd x = handle_params(body, t0);
  if (points.size() >= 5) {
    std::vector<Eigen::Vector3d> buffer;
    const auto& pts = subsample_into(points, buffer, kFitPoints);
    const int N = int(pts.size());
    Eigen::VectorXd y = fix_minor ? Eigen::VectorXd(x.head<4>()) : x;
    levenberg_marquardt(y, N, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
      Eigen::VectorXd full = x;
      full.head(v.size()) = v;
      handle_residuals(handle_torus(body, full), pts, r);
    });
    x.head(y.size()) = y;
  }
  Segment s = handle_torus(body, x);
  s.id = t0.id, s.pixels = t0.pixels, s.inliers = t0.inliers;
  set_residual(s, points);
  return s;
}

void set_extent(Segment& s, const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return;
  if (s.cls == PrimitiveClass::Cylinder) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : points) {
      const double t = s.axis.dot(p - s.point);
      lo = std::min(lo, t), hi = std::max(hi, t);
    }
    s.point += s.axis * (0.5 * (lo + hi));
    s.height = hi - lo;
  } else if (s.cls == PrimitiveClass::Plane) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : points) c += p;
    s.point = c / double(points.size());
  }
}

}  // namespace mereo::features::detail
