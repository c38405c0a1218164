// Least-squares refits of the shape table's classes (see fit.hpp).
#include "features/fit.hpp"

#include <cmath>
#include <type_traits>
#include <utility>

#include <Eigen/Dense>

namespace mereo::features::detail {

/// Levenberg-Marquardt stops when a step lowers the cost by less than this share of it (a
/// relative change of the RMS residual of 5e-9, far below any sensor's noise); at 1e-14 the last
/// steps took a third of the primitive search's refits (bench_pipeline, perf).
constexpr double kMinGain = 1e-8;

namespace {

/// Levenberg-Marquardt on residuals r(x) (N of them); `jacobian(x, r, J)` fills J at x (r holds
/// the residuals at x).
template <class F, class Jacobian>
void lm(Eigen::VectorXd& x, int N, const F& f, const Jacobian& jacobian) {
  const int P = int(x.size());
  Eigen::VectorXd r(N), r2(N);
  f(x, r);
  double cost = r.squaredNorm(), lambda = 1e-3;
  Eigen::MatrixXd J(N, P);
  for (int it = 0; it < 30; ++it) {
    jacobian(x, r, J);
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
        improved = cost - c2 > kMinGain * cost;
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

/// Shapes whose range residual has an analytic gradient over their packed parameters.
template <class S, class = void>
struct has_range_gradient : std::false_type {};
template <class S>
struct has_range_gradient<S, std::void_t<decltype(std::declval<const S&>().range_residual(
                                 Eigen::Vector3d(), Eigen::VectorXd(), static_cast<double*>(nullptr)))>>
    : std::true_type {};

}  // namespace

void levenberg_marquardt(Eigen::VectorXd& x, int N,
                         const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& f) {
  Eigen::VectorXd r2(N);
  lm(x, N, f, [&](const Eigen::VectorXd& at, const Eigen::VectorXd& r, Eigen::MatrixXd& J) {
    for (int k = 0; k < int(at.size()); ++k) {  // forward differences
      Eigen::VectorXd xp = at;
      const double h = 1e-6 * std::max(1.0, std::abs(at(k)));
      xp(k) += h;
      f(xp, r2);
      J.col(k) = (r2 - r) / h;
    }
  });
}

void set_residual(Segment& s, const std::vector<Eigen::Vector3d>& points) {
  double ss = 0;
  for (const auto& p : points) {
    const double d = s.signed_distance(p);
    ss += d * d;
  }
  s.residual = points.empty() ? 0.0 : std::sqrt(ss / double(points.size()));
}

const std::vector<Eigen::Vector3d>& subsample_into(const std::vector<Eigen::Vector3d>& points,
                                                   std::vector<Eigen::Vector3d>& buffer, std::size_t max_points) {
  if (points.size() <= max_points) return points;
  buffer.clear();
  const double stride = double(points.size()) / double(max_points);
  for (std::size_t k = 0; k < max_points; ++k) buffer.push_back(points[std::size_t(k * stride)]);
  return buffer;
}

Segment refit_points(const Segment& s0, const std::vector<Eigen::Vector3d>& points, Residual residual) {
  Segment s = s0;
  if (points.size() < 4) return s;
  s.visit([&](auto& g0) {
    using S = std::decay_t<decltype(g0)>;
    if (g0.fit_direct(points)) return;
    const S start = g0;
    Eigen::VectorXd x = start.pack();
    if (x.size() == 0) return;  // no iterative refit for this class
    std::vector<Eigen::Vector3d> buffer;
    const auto& pts = subsample_into(points, buffer, kFitPoints);
    const int N = int(pts.size());
    const auto f = [&](const Eigen::VectorXd& v, Eigen::VectorXd& r) {
      S t = start;
      t.unpack(v);
      if (residual == Residual::AlongRay)
        for (int i = 0; i < N; ++i) r(i) = t.range_residual(pts[i]);
      else
        for (int i = 0; i < N; ++i) r(i) = t.signed_distance(pts[i]);
    };
    bool closed_form = false;
    if constexpr (has_range_gradient<S>::value) {
      if (residual == Residual::AlongRay) {  // the gradient in closed form: one pass per Jacobian
        lm(x, N, f, [&](const Eigen::VectorXd& v, const Eigen::VectorXd&, Eigen::MatrixXd& J) {
          S t = start;
          t.unpack(v);
          Eigen::Matrix<double, 1, Eigen::Dynamic> row(v.size());
          for (int i = 0; i < N; ++i) {
            t.range_residual(pts[i], v, row.data());
            J.row(i) = row;
          }
        });
        closed_form = true;
      }
    }
    if (!closed_form) levenberg_marquardt(x, N, f);
    g0 = start;
    g0.unpack(x);
  });
  set_residual(s, points);
  return s;
}

void set_extent(Segment& s, const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return;
  s.visit([&](auto& g) { g.set_extent(points); });
}

}  // namespace mereo::features::detail
