#include "mereo/features/edges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "features/pixels.hpp"
#include "mereo/core/error.hpp"
#include "mereo/extension/projection.hpp"

namespace mereo::features {

namespace {

using Pt = Eigen::Vector2f;
constexpr double kDeg = M_PI / 180;
/// A straight run this many times longer than the longest chord an arc's ellipse allows within the
/// split tolerance is a line.
constexpr double kStraightChord = 1.2;

/// Where a chain is cut into straight pieces: indices into `p`, first and last included
/// (Douglas-Peucker: split where the point farthest from the chord is farther than `tol`).
std::vector<int> split_points(const std::vector<Pt>& p, double tol) {
  std::vector<int> cuts = {0, int(p.size()) - 1};
  std::vector<std::pair<int, int>> stack = {{0, int(p.size()) - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    const Eigen::Vector2d a = p[i].cast<double>(), d = p[j].cast<double>() - a;
    const double len = d.norm();
    int far = -1;
    double worst = tol;
    for (int k = i + 1; k < j; ++k) {
      const Eigen::Vector2d q = p[k].cast<double>() - a;
      const double dist = len > 1e-9 ? std::abs(d.x() * q.y() - d.y() * q.x()) / len : q.norm();
      if (dist > worst) worst = dist, far = k;
    }
    if (far < 0) continue;
    cuts.push_back(far);
    stack.push_back({i, far});
    stack.push_back({far, j});
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  return cuts;
}

/// The signed turn from piece (a, b) to piece (b, c), radians.
double turn(const Pt& a, const Pt& b, const Pt& c) {
  const Eigen::Vector2d u = (b - a).cast<double>(), v = (c - b).cast<double>();
  return std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
}

/// An ellipse fitted to points i..j of a chain, as an arc, with its fit errors (pixels).
struct ArcFit {
  shapes::Arc arc;
  double rms = 0, worst = 0;
  /// The Sampson distance of q to the ellipse (its implicit function over its gradient), pixels.
  double distance(const Pt& q) const {
    const double a = arc.axes_px.x(), b = arc.axes_px.y(), ang = arc.angle_deg * kDeg;
    const double dx = q.x() - arc.center_px.x(), dy = q.y() - arc.center_px.y();
    const double x = std::cos(ang) * dx + std::sin(ang) * dy, y = -std::sin(ang) * dx + std::cos(ang) * dy;
    const double F = x * x / (a * a) + y * y / (b * b) - 1, gx = 2 * x / (a * a), gy = 2 * y / (b * b);
    return std::abs(F) / std::max(1e-12, std::hypot(gx, gy));
  }
};

/// The scatter matrix of the conic's monomials (x^2, xy, y^2, x, y, 1) over points taken
/// relative to `origin`: an arc grows by adding its points, and is fitted from the sums alone.
struct ConicScatter {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Zero();
  int n = 0;
  void add(const Pt& q) {
    const double x = q.x() - origin.x(), y = q.y() - origin.y();
    Eigen::Matrix<double, 6, 1> d;
    d << x * x, x * y, y * y, x, y, 1;
    S.selfadjointView<Eigen::Upper>().rankUpdate(d);
    ++n;
  }
};

/// The ellipse of least algebraic error under 4AC - B^2 = 1 (Fitzgibbon, Pilu and Fisher 1999,
/// in the numerically stable form of Halir and Flusser 1998); nullopt when the points hold none.
std::optional<shapes::Arc> direct_ellipse(const ConicScatter& c) {
  if (c.n < 6) return std::nullopt;
  const Eigen::Matrix<double, 6, 6> S = c.S.selfadjointView<Eigen::Upper>();
  const Eigen::Matrix3d S1 = S.topLeftCorner<3, 3>(), S2 = S.topRightCorner<3, 3>(), S3 = S.bottomRightCorner<3, 3>();
  Eigen::FullPivLU<Eigen::Matrix3d> lu(S3);
  if (!lu.isInvertible()) return std::nullopt;
  const Eigen::Matrix3d T = -lu.solve(S2.transpose());
  const Eigen::Matrix3d M = S1 + S2 * T;
  Eigen::Matrix3d N;  // the constraint's inverse applied: C1^-1 M
  N.row(0) = M.row(2) / 2, N.row(1) = -M.row(1), N.row(2) = M.row(0) / 2;
  // its real eigenvalues from the characteristic cubic (closed form: this runs once per growth
  // step of every arc), each one's eigenvector from two rows of N - lambda I; the ellipse's is the
  // one with 4AC - B^2 > 0
  const double tr = N.trace(), dn = N.determinant();
  const double minors = N(0, 0) * N(1, 1) - N(0, 1) * N(1, 0) + N(0, 0) * N(2, 2) - N(0, 2) * N(2, 0) +
                        N(1, 1) * N(2, 2) - N(1, 2) * N(2, 1);
  const double a = -tr, b = minors, cc = -dn;  // lambda^3 + a lambda^2 + b lambda + cc = 0
  const double Q = (a * a - 3 * b) / 9, R = (2 * a * a * a - 9 * a * b + 27 * cc) / 54;
  double roots[3];
  int n_roots = 0;
  if (R * R < Q * Q * Q) {
    const double th = std::acos(std::clamp(R / std::sqrt(Q * Q * Q), -1.0, 1.0));
    for (int k = 0; k < 3; ++k) roots[n_roots++] = -2 * std::sqrt(Q) * std::cos((th + 2 * M_PI * k) / 3) - a / 3;
  } else {
    const double A = -std::copysign(std::cbrt(std::abs(R) + std::sqrt(R * R - Q * Q * Q)), R);
    roots[n_roots++] = A + (A != 0 ? Q / A : 0) - a / 3;
  }
  std::optional<Eigen::Vector3d> a1;
  for (int k = 0; k < n_roots && !a1; ++k) {
    const Eigen::Matrix3d L = N - roots[k] * Eigen::Matrix3d::Identity();
    Eigen::Vector3d v = L.row(0).cross(L.row(1)).transpose();
    for (const Eigen::Vector3d& w : {Eigen::Vector3d(L.row(0).cross(L.row(2))), Eigen::Vector3d(L.row(1).cross(L.row(2)))})
      if (w.squaredNorm() > v.squaredNorm()) v = w;
    if (v.squaredNorm() > 0 && 4 * v(0) * v(2) - v(1) * v(1) > 0) a1 = v.normalized();
  }
  if (!a1) return std::nullopt;
  const Eigen::Vector3d a2 = T * *a1;
  double A = (*a1)(0), B = (*a1)(1), C = (*a1)(2), D = a2(0), E = a2(1), F = a2(2);
  if (A + C < 0) A = -A, B = -B, C = -C, D = -D, E = -E, F = -F;  // the quadratic form positive definite
  const double det = 4 * A * C - B * B;
  const double x0 = (B * E - 2 * C * D) / det, y0 = (B * D - 2 * A * E) / det;
  const double Fc = F + (D * x0 + E * y0) / 2;  // the conic's value at its centre
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> q((Eigen::Matrix2d() << A, B / 2, B / 2, C).finished());
  const double l1 = q.eigenvalues()(0), l2 = q.eigenvalues()(1);
  if (!(Fc < 0 && l1 > 0)) return std::nullopt;
  shapes::Arc arc;
  arc.center_px = c.origin + Eigen::Vector2d(x0, y0);
  arc.axes_px = {std::sqrt(-Fc / l1), std::sqrt(-Fc / l2)};  // the smaller eigenvalue: the major axis
  const Eigen::Vector2d major = q.eigenvectors().col(0);
  arc.angle_deg = std::fmod(std::atan2(major.y(), major.x()) / kDeg + 360.0, 180.0);
  return arc;
}

/// The ellipse of `c`, judged on points i..j of the chain: its errors and the part of it seen.
std::optional<ArcFit> fit_arc(const ConicScatter& c, const std::vector<Pt>& p, int i, int j,
                              const EdgePrimitiveOptions& o, double max_axis) {
  auto e = direct_ellipse(c);
  if (!e || !std::isfinite(e->axes_px.x()) || e->axes_px.y() < o.min_minor_px || e->axes_px.x() > max_axis)
    return std::nullopt;
  ArcFit f;
  f.arc = *e;
  const double a = f.arc.axes_px.x(), b = f.arc.axes_px.y();
  const double cs = std::cos(f.arc.angle_deg * kDeg), sn = std::sin(f.arc.angle_deg * kDeg);
  double sum = 0, t0 = 0, t = 0;
  for (int k = i; k <= j; ++k) {
    const double d = f.distance(p[k]);
    sum += d * d, f.worst = std::max(f.worst, d);
    const double dx = p[k].x() - f.arc.center_px.x(), dy = p[k].y() - f.arc.center_px.y();
    const double x = cs * dx + sn * dy, y = -sn * dx + cs * dy;  // in the ellipse's frame
    const double tk = std::atan2(y / b, x / a);
    if (k == i) t0 = t = tk;
    else t += std::remainder(tk - t, 2 * M_PI);  // unwrapped along the chain
  }
  f.rms = std::sqrt(sum / (j - i + 1));
  const double lo = std::min(t0, t), span = std::min(2 * M_PI, std::abs(t - t0));
  f.arc.start_deg = std::fmod(lo / kDeg + 720.0, 360.0);
  f.arc.end_deg = f.arc.start_deg + span / kDeg;
  return f;
}

/// The colour at a sub-pixel point (nearest pixel); false outside the image.
bool colour_at(const ColorImage& im, const Eigen::Vector2d& q, Eigen::Vector3d& sum) {
  const int u = int(std::lround(q.x())), v = int(std::lround(q.y()));
  if (u < 0 || v < 0 || u >= im.cols() || v >= im.rows()) return false;
  const std::uint8_t* c = im.ptr(v, u);
  sum += Eigen::Vector3d(c[0], c[1], c[2]) / 255.0;
  return true;
}

/// Mean colours at point +- offset * normal over samples (point, unit normal).
template <class Samples>
shapes::EdgeSides sides_of(const ColorImage& im, const Samples& samples, double offset) {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  int na = 0, nb = 0;
  for (const auto& [q, n] : samples) {
    na += colour_at(im, q + offset * n, a);
    nb += colour_at(im, q - offset * n, b);
  }
  shapes::EdgeSides s;
  if (na) s.a = a / na;
  if (nb) s.b = b / nb;
  return s;
}

/// The nearest valid point of `cloud` within `w` pixels of (u, v): the occluding side of a depth edge.
std::optional<Eigen::Vector3d> nearest_point(const Cloud& cloud, const Pt& q, int w) {
  const int u0 = int(std::lround(q.x())), v0 = int(std::lround(q.y()));
  const float* best = nullptr;
  for (int v = std::max(0, v0 - w); v <= std::min(cloud.rows() - 1, v0 + w); ++v)
    for (int u = std::max(0, u0 - w); u <= std::min(cloud.cols() - 1, u0 + w); ++u) {
      const float* p = cloud.ptr(v, u);
      if (valid_point(p) && (!best || p[2] < best[2])) best = p;
    }
  if (!best) return std::nullopt;
  return Eigen::Vector3d(best[0], best[1], best[2]);
}

/// An edge pixel's 3-D point: the nearest depth within `w` pixels (the occluding side of a depth
/// edge, from a min filter of the depth), on the pixel's own ray; the nearest point itself where
/// the pixel has none.
class Lifter {
 public:
  Lifter(const Cloud& cloud, int w) : cloud_(cloud), w_(w) {
    cv::Mat z(cloud.rows(), cloud.cols(), CV_32F);
    for (int v = 0; v < cloud.rows(); ++v)
      for (int u = 0; u < cloud.cols(); ++u) {
        const float* p = cloud.ptr(v, u);
        z.at<float>(v, u) = valid_point(p) ? p[2] : std::numeric_limits<float>::infinity();
      }
    cv::erode(z, near_, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * w + 1, 2 * w + 1)));
  }
  std::optional<Eigen::Vector3d> operator()(const Pt& q) const {
    const int u = std::clamp(int(std::lround(q.x())), 0, cloud_.cols() - 1);
    const int v = std::clamp(int(std::lround(q.y())), 0, cloud_.rows() - 1);
    const float zn = near_.at<float>(v, u);
    if (!std::isfinite(zn)) return std::nullopt;
    const float* p = cloud_.ptr(v, u);
    if (valid_point(p)) return Eigen::Vector3d(p[0], p[1], p[2]) * (double(zn) / p[2]);
    return nearest_point(cloud_, q, w_);
  }

 private:
  const Cloud& cloud_;
  int w_;
  cv::Mat near_;
};

/// Points of chain i..j lifted to 3-D (at most about 64, evenly spaced: enough for a line or a
/// circle); empty when fewer than half of those tried have depth.
std::vector<Eigen::Vector3d> lifted_points(const std::vector<Pt>& p, int i, int j, const Lifter& lift) {
  std::vector<Eigen::Vector3d> out;
  const int step = std::max(1, (j - i + 1) / 64);
  int tried = 0;
  for (int k = i; k <= j; k += step, ++tried)
    if (auto x = lift(p[k])) out.push_back(*x);
  if (2 * int(out.size()) < tried) out.clear();
  return out;
}

/// Centroid and covariance eigen-decomposition (ascending) of points.
struct Pca {
  Eigen::Vector3d mean;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
};
Pca pca(const std::vector<Eigen::Vector3d>& x) {
  Pca r;
  r.mean = Eigen::Vector3d::Zero();
  for (const auto& q : x) r.mean += q;
  r.mean /= double(x.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& q : x) C += (q - r.mean) * (q - r.mean).transpose();
  r.eig.compute(C / double(x.size()));
  return r;
}

/// Keeps the points within 3 median distances (at least `floor`) of a fit.
template <class Dist>
void drop_outliers(std::vector<Eigen::Vector3d>& x, Dist dist, double floor) {
  std::vector<double> d;
  for (const auto& q : x) d.push_back(dist(q));
  std::vector<double> s = d;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  const double keep = std::max(floor, 3 * s[s.size() / 2]);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (d[k] <= keep) out.push_back(x[k]);
  x.swap(out);
}

/// A line's 3-D segment from its lifted points (kept when they fit it within tol_1m * z).
void lift_to_3d(shapes::Line& l, std::vector<Eigen::Vector3d> x, double tol_1m, double& residual) {
  if (x.size() < 5) return;
  for (int pass = 0; pass < 2; ++pass) {
    const Pca f = pca(x);
    const Eigen::Vector3d a = f.eig.eigenvectors().col(2);
    const auto dist = [&](const Eigen::Vector3d& q) { return shapes::across(q - f.mean, a).norm(); };
    if (pass == 0) {
      drop_outliers(x, dist, 0.25 * tol_1m * f.mean.z());
      if (x.size() < 5) return;
      continue;
    }
    double sum = 0, lo = 1e300, hi = -1e300;
    for (const auto& q : x) {
      sum += dist(q) * dist(q);
      lo = std::min(lo, a.dot(q - f.mean)), hi = std::max(hi, a.dot(q - f.mean));
    }
    const double rms = std::sqrt(sum / x.size());
    if (!(rms <= tol_1m * f.mean.z())) return;
    l.lifted = true;
    l.axis = a;
    l.point = f.mean + a * (lo + hi) / 2;
    l.length = hi - lo;
    residual = rms;
  }
}

/// An arc's 3-D circle from its lifted points: a plane, then a circle in it (Kasa).
void lift_to_3d(shapes::Arc& arc, std::vector<Eigen::Vector3d> x, double tol_1m, double& residual) {
  if (x.size() < 8) return;
  for (int pass = 0; pass < 2; ++pass) {
    const Pca f = pca(x);
    const Eigen::Vector3d ev = f.eig.eigenvalues();
    if (!(ev(1) > 1e-3 * ev(2))) return;  // a straight run: no plane to hold a circle
    const Eigen::Vector3d n = f.eig.eigenvectors().col(0), e1 = f.eig.eigenvectors().col(2), e2 = n.cross(e1);
    // Kasa's circle fit in the plane: x^2 + y^2 + D x + E y + F = 0
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d B = Eigen::Vector3d::Zero();
    for (const auto& q : x) {
      const Eigen::Vector3d r(e1.dot(q - f.mean), e2.dot(q - f.mean), 1.0);
      A += r * r.transpose();
      B -= r * (r.x() * r.x() + r.y() * r.y());
    }
    const Eigen::Vector3d s = A.ldlt().solve(B);
    const Eigen::Vector2d c(-s(0) / 2, -s(1) / 2);
    const double rad = std::sqrt(std::max(0.0, c.squaredNorm() - s(2)));
    const Eigen::Vector3d centre = f.mean + c.x() * e1 + c.y() * e2;
    const auto dist = [&](const Eigen::Vector3d& q) {
      const Eigen::Vector3d d = q - centre;
      const double h = n.dot(d);
      return std::hypot((d - n * h).norm() - rad, h);
    };
    if (!(rad > 0 && rad < 2.0)) return;
    if (pass == 0) {
      drop_outliers(x, dist, 0.25 * tol_1m * f.mean.z());
      if (x.size() < 8) return;
      continue;
    }
    double sum = 0;
    for (const auto& q : x) sum += dist(q) * dist(q);
    const double rms = std::sqrt(sum / x.size());
    if (!(rms <= tol_1m * f.mean.z())) return;
    arc.lifted = true;
    arc.center = centre;
    arc.normal = n.dot(centre) > 0 ? Eigen::Vector3d(-n) : n;  // facing the camera
    arc.radius = rad;
    residual = rms;
  }
}

/// The chain's pixels i..j as indices v * W + u, each once, in chain order.
std::vector<int> pixels_of(const std::vector<Pt>& p, int i, int j, int W, int H) {
  std::vector<int> out;
  for (int k = i; k <= j; ++k) {
    const int u = std::clamp(int(std::lround(p[k].x())), 0, W - 1), v = std::clamp(int(std::lround(p[k].y())), 0, H - 1);
    if (out.empty() || out.back() != v * W + u) out.push_back(v * W + u);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

std::vector<Segment> fit_edge_primitives(const std::vector<signal::EdgeChain>& chains, const ColorImage& color,
                                         const Cloud* cloud, const EdgePrimitiveOptions& o) {
  check_options(o);
  if (color.empty()) throw InputError("fit_edge_primitives: the colour image is empty");
  if (cloud && !cloud->empty() && (cloud->rows() != color.rows() || cloud->cols() != color.cols()))
    throw InputError("fit_edge_primitives: the cloud and the colour image differ in size");
  const bool lift = o.lift && cloud && !cloud->empty();
  std::optional<Lifter> lifter;
  if (lift) lifter.emplace(*cloud, o.lift_window_px);
  const int W = color.cols(), H = color.rows();
  const double max_axis = 2.0 * std::max(W, H);
  std::vector<Segment> arcs, lines;

  std::vector<Pt> rotated;
  for (const auto& chain : chains) {
    const std::vector<Pt>* points = &chain.points;
    if (points->size() < 2) continue;
    std::vector<int> cut = split_points(*points, o.split_tolerance_px);
    if (const auto& q = *points; cut.size() > 3 && (q.front() - q.back()).norm() <= 2) {
      // a closed chain starts where its walk happened to start, maybe inside an arc: start it at
      // its sharpest corner instead, so that no arc is cut in two (a smooth ring stays as it is)
      auto turn_of = [&](std::size_t v) {  // at vertex cut[v]; vertex 0 between the last piece and the first
        return std::abs(v == 0 ? turn(q[cut[cut.size() - 2]], q[0], q[cut[1]]) : turn(q[cut[v - 1]], q[cut[v]], q[cut[v + 1]]));
      };
      std::size_t sharpest = 0;
      for (std::size_t v = 1; v + 1 < cut.size(); ++v)
        if (turn_of(v) > turn_of(sharpest)) sharpest = v;
      if (sharpest > 0 && turn_of(sharpest) > o.max_turn_deg * kDeg) {
        rotated.assign(q.begin() + cut[sharpest], q.end() - 1);
        rotated.insert(rotated.end(), q.begin(), q.begin() + cut[sharpest] + 1);
        points = &rotated;
        cut = split_points(rotated, o.split_tolerance_px);
      }
    }
    const auto& p = *points;
    // the segment of a line or an arc fitted to points i..j: lifted where the depth allows, with
    // its edge pixels and their colour
    auto segment_of = [&](auto shape, int i, int j) {
      double residual = 0;
      if (lift) lift_to_3d(shape, lifted_points(p, i, j, *lifter), o.lift_tolerance, residual);
      Segment s{Geometry(shape)};
      s.residual = residual;
      s.pixels = pixels_of(p, i, j, W, H);
      s.inliers = s.pixels.size();
      detail::set_color(s, &color);
      return s;
    };
    int pieces = int(cut.size()) - 1;
    auto turn_at = [&](int k) { return turn(p[cut[k]], p[cut[k + 1]], p[cut[k + 2]]); };  // piece k to k + 1
    const double max_turn = o.max_turn_deg * kDeg;
    // a straight piece longer than any chord within split_tolerance_px of the ellipse grown so far
    // (where it bends least, radius a^2 / b) is a line beside the arc, not part of it: a
    // cylinder's side after its base's arc, which a bigger ellipse would otherwise take in too
    // (lines longer than the ellipse's diameter are not judged by it: a small arc at a corner)
    auto too_straight = [&](const shapes::Arc& a, double length) {
      const double big = std::max(a.axes_px.x(), a.axes_px.y()), small = std::min(a.axes_px.x(), a.axes_px.y());
      const double chord = std::sqrt(8 * big * big / std::max(small, 1e-6) * o.split_tolerance_px);
      return length > kStraightChord * chord && length >= o.min_line_px && length <= 2 * big;
    };
    // points i..j within the split tolerance of their chord
    auto straight = [&](int i, int j) {
      const Eigen::Vector2f d = (p[j] - p[i]).normalized();
      for (int q = i + 1; q < j; ++q)
        if (std::abs(d.x() * (p[q] - p[i]).y() - d.y() * (p[q] - p[i]).x()) > o.split_tolerance_px)
          return false;
      return true;
    };
    for (int k = 0; k < pieces;) {
      // an arc: pieces k..e turning the same way, grown while the ellipse holds their points
      std::optional<ArcFit> best;
      std::vector<std::optional<ArcFit>> fit_upto;  // the fit of pieces k..e, at e - k
      int best_e = k, failed_e = -1;
      bool at_line = false;  // the growth stopped at a line (no bisection into it)
      ConicScatter grown;  // of points cut[k] .. cut[e + 1]
      grown.origin = p[cut[k]].cast<double>();
      grown.add(p[cut[k]]);
      auto holds = [&](const ConicScatter& c, int j) {
        auto f = fit_arc(c, p, cut[k], j, o, max_axis);
        return f && f->rms <= o.arc_tolerance_px && f->worst <= o.max_arc_error_px ? f : std::nullopt;
      };
      if (k + 1 < pieces && std::abs(turn_at(k)) <= max_turn) {
        const bool left = turn_at(k) > 0;
        for (int q = cut[k] + 1; q <= cut[k + 1]; ++q) grown.add(p[q]);
        fit_upto.emplace_back();
        for (int e = k + 1;; ++e) {
          // the straight run of pieces ending with e: a line when longer than the arc's chords
          int r = e;
          while (r - 1 > k && straight(cut[r - 1], cut[e + 1])) --r;
          if (best && best->arc.span_deg() >= o.min_arc_span_deg && too_straight(best->arc, (p[cut[e + 1]] - p[cut[r]]).norm())) {
            best = fit_upto[std::size_t(r - 1 - k)], best_e = r - 1, failed_e = r, at_line = true;
            break;
          }
          for (int q = cut[e] + 1; q <= cut[e + 1]; ++q) grown.add(p[q]);
          fit_upto.push_back(holds(grown, cut[e + 1]));
          if (const auto& f = fit_upto.back()) best = f, best_e = e;
          else if (best) {
            failed_e = e;
            break;
          }
          if (e + 1 >= pieces || (turn_at(e) > 0) != left || std::abs(turn_at(e)) > max_turn) break;
        }
      }
      if (best && failed_e >= 0 && !at_line) {
        // the arc may end inside the piece that broke it (where the outline meets another's):
        // the last point of that piece it still holds, by bisection, its added points within the
        // RMS tolerance too (not bent into the corner); the rest of the piece stays
        const int end = cut[best_e + 1];
        ConicScatter upto;  // of points cut[k] .. end
        upto.origin = grown.origin;
        for (int q = cut[k]; q <= end; ++q) upto.add(p[q]);
        int lo = end, hi = cut[failed_e + 1];
        while (hi - lo > 1) {
          const int mid = (lo + hi) / 2;
          ConicScatter c = upto;
          for (int q = end + 1; q <= mid; ++q) c.add(p[q]);
          auto f = holds(c, mid);
          double sum = 0;
          for (int q = end + 1; f && q <= mid; ++q) sum += f->distance(p[q]) * f->distance(p[q]);
          if (f && sum <= (mid - end) * o.arc_tolerance_px * o.arc_tolerance_px) best = f, lo = mid;
          else hi = mid;
        }
        if (lo > cut[best_e + 1]) cut[best_e + 1] = lo;
      }
      // nor does an arc begin with such a line, one piece or a straight run of them (the side
      // before the base's arc): the run becomes one piece, a line, and the arc grows after it
      if (best) {
        int r = k;
        while (r + 1 <= best_e && straight(cut[k], cut[r + 2])) ++r;
        if (too_straight(best->arc, (p[cut[r + 1]] - p[cut[k]]).norm())) {
          cut.erase(cut.begin() + k + 1, cut.begin() + r + 1);
          pieces = int(cut.size()) - 1;
          best.reset();
        }
      }
      if (best && best->arc.span_deg() >= o.min_arc_span_deg) {
        shapes::Arc& a = best->arc;
        const int i = cut[k], j = cut[best_e + 1];
        std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> samples;
        for (double t = a.start_deg; t <= a.end_deg; t += 3) {
          const double tr = t * kDeg, ar = a.angle_deg * kDeg;
          const Eigen::Vector2d g(std::cos(tr) / a.axes_px.x(), std::sin(tr) / a.axes_px.y());
          const Eigen::Vector2d n(std::cos(ar) * g.x() - std::sin(ar) * g.y(), std::sin(ar) * g.x() + std::cos(ar) * g.y());
          samples.push_back({a.at(t), -n.normalized()});  // a: inside
        }
        a.sides = sides_of(color, samples, o.side_offset_px);
        arcs.push_back(segment_of(a, i, j));
        k = best_e + 1;
        continue;
      }
      // a line: one straight piece, refitted by total least squares
      const int i = cut[k], j = cut[k + 1];
      ++k;
      if ((p[j] - p[i]).norm() < o.min_line_px) continue;
      Eigen::Vector2d m = Eigen::Vector2d::Zero();
      for (int q = i; q <= j; ++q) m += p[q].cast<double>();
      m /= double(j - i + 1);
      Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
      for (int q = i; q <= j; ++q) C += (p[q].cast<double>() - m) * (p[q].cast<double>() - m).transpose();
      Eigen::Vector2d d = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(C).eigenvectors().col(1);
      if (d.dot((p[j] - p[i]).cast<double>()) < 0) d = -d;
      shapes::Line l;
      l.start_px = m + d * d.dot(p[i].cast<double>() - m);
      l.end_px = m + d * d.dot(p[j].cast<double>() - m);
      const Eigen::Vector2d left(d.y(), -d.x());  // the screen's left walking from start to end (y down)
      std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> samples;
      const double len = l.length_px();
      for (double t = 0; t <= len; t += 2) samples.push_back({l.start_px + d * t, left});
      l.sides = sides_of(color, samples, o.side_offset_px);
      lines.push_back(segment_of(l, i, j));
    }
  }
  std::vector<Segment> out = std::move(arcs);
  for (auto& l : lines) out.push_back(std::move(l));
  for (std::size_t k = 0; k < out.size(); ++k) out[k].id = int(k);
  return out;
}

std::vector<Segment> detect_edge_primitives(const Frame& frame, const EdgePrimitiveOptions& o) {
  if (frame.color.empty()) throw InputError(frame.source + ": the frame has no colour image to find edges in");
  const auto chains = signal::detect_edges(frame.color, o.edges);
  Cloud cloud;
  if (o.lift && !frame.depth.empty()) cloud = frame.cloud.empty() ? extension::back_project(frame) : frame.cloud;
  return fit_edge_primitives(chains, frame.color, cloud.empty() ? nullptr : &cloud, o);
}

}  // namespace mereo::features
