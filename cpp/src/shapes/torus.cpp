#include "mereo/shapes/torus.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace mereo::shapes {

double Torus::half_extent_along(const Eigen::Vector3d& dir) const {
  const double c = std::abs(normal.normalized().dot(dir));
  const double sn = std::sqrt(std::max(0.0, 1 - c * c));
  return sn * (major_radius + minor_radius) + c * minor_radius;
}

double Torus::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d* n) const {
  const Eigen::Vector3d q = x - center;
  const Eigen::Vector3d inplane = q - normal * normal.dot(q);
  const double rho = inplane.norm();
  const Eigen::Vector3d ring = rho > 0 ? Eigen::Vector3d(inplane / rho * major_radius) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d t = q - ring;
  const double l = t.norm();
  if (n) *n = l > 0 ? Eigen::Vector3d(t / l) : normal;
  return l - minor_radius;
}

double Torus::surface_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d a = normal.normalized();
  const Eigen::Vector3d q = p - center;
  const double h = a.dot(q);
  const double rho = (q - a * h).norm();
  return std::max(0.0, std::hypot(rho - major_radius, h) - minor_radius);
}

std::optional<Torus> Torus::from_sample(const Eigen::Vector3d* p, const Eigen::Vector3d* n, const Limits& l) {
  const double min_minor = l.min_minor_radius, max_minor = l.max_minor_radius;
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
  Torus s;
  s.center = centre;
  s.normal = nn / std::sqrt(l2);
  s.major_radius = (a - centre).norm();
  s.minor_radius = best_r;
  // the fourth tube centre must lie on the ring too
  const Eigen::Vector3d d = p[3] - best_r * n[3];
  if (std::abs((d - centre).norm() - s.major_radius) > 0.1 * s.major_radius + 0.002) return std::nullopt;
  return s;
}

Eigen::VectorXd Torus::pack() const {
  Eigen::VectorXd v(8);
  v << center, normal, major_radius, minor_radius;
  return v;
}

void Torus::unpack(const Eigen::VectorXd& v) {
  center = v.head<3>();
  normal = v.segment<3>(3).normalized();
  major_radius = v(6);
  minor_radius = v(7);
}

void Torus::fields(FieldList& out, bool) const {
  out.push_back({"center", center});
  out.push_back({"normal", normal});
  out.push_back({"major_radius", major_radius});
  out.push_back({"minor_radius", minor_radius});
}

bool Torus::set_field(const std::string& key, const FieldValue& v) {
  if ((key == "center" || key == "point") && vector3(v)) return center = *vector3(v), true;
  if ((key == "normal" || key == "axis") && vector3(v)) return normal = vector3(v)->normalized(), true;
  if ((key == "major_radius" || key == "radius") && number(v)) return major_radius = *number(v), true;
  if (key == "minor_radius" && number(v)) return minor_radius = *number(v), true;
  return false;
}

std::optional<double> Torus::attribute(const std::string& key) const {
  if (key == "radius" || key == "major_radius") return major_radius;
  if (key == "minor_radius") return minor_radius;
  return std::nullopt;
}

void Torus::outline(Outline& out) const {
  out.lines.push_back(circle(center, normal.normalized(), major_radius));
  out.lines.push_back(circle(center, normal.normalized(), major_radius + minor_radius));
}

void Torus::tracked(TrackedParams& t) const {
  for (int i = 0; i < 3; ++i) t.add(center(i), false);
  t.add(major_radius, true);
  t.add(minor_radius, true);
}

}  // namespace mereo::shapes
