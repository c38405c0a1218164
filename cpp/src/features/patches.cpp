// Bounded planar patches (mereo/features/patches.hpp).
#include "mereo/features/patches.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "features/pixels.hpp"
#include "mereo/core/error.hpp"
#include "mereo/shapes/patch.hpp"

namespace mereo::features {
namespace {

/// A plane fitted to a growing set of points: sums about a fixed reference point (numerics).
struct PlaneSums {
  Eigen::Vector3d ref = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();
  std::size_t n = 0;
  void add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - ref;
    s += q, ss += q * q.transpose(), ++n;
  }
  Eigen::Vector3d centroid() const { return ref + s / double(n); }
  /// The normal of least scatter, on the side of `near`.
  Eigen::Vector3d normal(const Eigen::Vector3d& near) const {
    const Eigen::Vector3d m = s / double(n);
    const Eigen::Matrix3d c = ss / double(n) - m * m.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(c);
    Eigen::Vector3d out = es.eigenvectors().col(0);
    return out.dot(near) < 0 ? Eigen::Vector3d(-out) : out;
  }
};

/// The frame on the grid: cell k is pixel (gv * step, gu * step).
struct Grid {
  const Cloud& cloud;
  const NormalMap& normals;
  int step, gw, gh, W;
  std::vector<int> rep;  // each cell's pixel: the first of its block with a point and a normal
  Grid(const Cloud& c, const NormalMap& n, int s)
      : cloud(c), normals(n), step(s), gw((c.cols() + s - 1) / s), gh((c.rows() + s - 1) / s), W(c.cols()) {
    // a surface whose depth is sparse (dark, seen at a grazing angle: a table top from 3 m) keeps
    // its cells where one pixel of each block has depth
    rep.resize(std::size_t(gw) * std::size_t(gh));
    for (int k = 0; k < gw * gh; ++k) {
      const int u0 = (k % gw) * step, v0 = (k / gw) * step;
      int best = v0 * W + u0;
      for (int v = v0; v < std::min(c.rows(), v0 + step) && best == v0 * W + u0 && !usable(best); ++v)
        for (int u = u0; u < std::min(c.cols(), u0 + step); ++u)
          if (usable(v * W + u)) {
            best = v * W + u;
            break;
          }
      rep[std::size_t(k)] = best;
    }
  }
  bool usable(int i) const {
    return valid_point(cloud.data() + 3 * std::size_t(i)) && std::isfinite(normals.data()[3 * std::size_t(i)]);
  }
  int pixel(int k) const { return rep[std::size_t(k)]; }
  Eigen::Vector3d p(int k) const {
    const float* q = cloud.data() + 3 * std::size_t(pixel(k));
    return Eigen::Vector3d(q[0], q[1], q[2]);
  }
  Eigen::Vector3d n(int k) const {
    const float* q = normals.data() + 3 * std::size_t(pixel(k));
    return Eigen::Vector3d(q[0], q[1], q[2]);
  }
  bool valid(int k) const { return usable(pixel(k)); }
};

/// The size of a pixel seen at 1 m (1 / focal length), from the cloud: the median difference of
/// x / z between horizontal neighbours on a few rows.
double angular_pixel(const Cloud& cloud) {
  std::vector<double> d;
  const int H = cloud.rows(), W = cloud.cols();
  for (int v = H / 16; v < H; v += std::max(1, H / 8))
    for (int u = 0; u + 1 < W; ++u) {
      const float *a = cloud.ptr(v, u), *b = cloud.ptr(v, u + 1);
      if (valid_point(a) && valid_point(b)) d.push_back(double(b[0]) / b[2] - double(a[0]) / a[2]);
    }
  const double q = detail::quantile(d, 0.5);
  return q > 0 ? q : 1.0 / 525;
}

/// A point's distance to a patch's plane at depth z that still counts as on it
/// (PatchOptions::epsilon at 1 m, growing with z^2).
double plane_tolerance(double epsilon, double z) { return epsilon * std::max(1.0, z * z); }

/// A depth difference at depth z that parts what lies behind from what lies at it (10 cm, or 3%).
double far_step(double z) { return std::max(0.1, 0.03 * z); }

/// The footprint on its plane (normal n) of the pixel at x; `a` is a pixel's angle. Seen more
/// obliquely than 75 degrees, a pixel counts as at 75 (grazing far floors).
double footprint(const Eigen::Vector3d& x, const Eigen::Vector3d& n, double a) {
  const double facing = std::max(0.25, std::abs(n.dot(x.normalized())));
  return (x.z() * a) * (x.z() * a) / facing;
}

/// What lies beyond a patch's edge at pixel (v, u), outwards along (dv, du) for at most `reach`
/// pixels: +1 where the depth steps behind by more than far_step, -1 where it steps in front, 0
/// where another surface meets the patch's plane without a step (a floor below a wall's foot, a
/// box's side at its front's edge) or nothing is found. The plane (normal n through c) runs on for
/// the rim the normals' window leaves (points within half its tolerance); a step is measured
/// between pixels two apart, as the depth filter spreads it over a few. With rising_hides, a
/// surface that leaves the plane on its normal's side (towards the camera: a cushion standing on a
/// table top meets it at a concave edge, without a step) hides it too: -1.
int depth_step(const Cloud& cloud, int v, int u, int dv, int du, int reach, const Eigen::Vector3d& n,
               const Eigen::Vector3d& c, double epsilon, bool rising_hides = false) {
  const int W = cloud.cols(), H = cloud.rows();
  const double z = cloud.ptr(v, u)[2], margin = far_step(z), off = 0.5 * plane_tolerance(epsilon, z);
  const float* older = cloud.ptr(v, u);  // the valid pixel two back (one back at first)
  const float* newer = nullptr;
  for (int k = 1; k <= reach; ++k) {
    const int vk = v + k * dv, uk = u + k * du;
    if (vk < 0 || vk >= H || uk < 0 || uk >= W) return 0;
    const float* q = cloud.ptr(vk, uk);
    if (!valid_point(q)) continue;
    if (std::abs(q[2] - older[2]) > margin) return q[2] > older[2] ? 1 : -1;
    if (const double h = n.dot(Eigen::Vector3d(q[0], q[1], q[2]) - c); std::abs(h) > off) return rising_hides && h > 0 ? -1 : 0;
    if (newer) older = newer;
    newer = q;
  }
  return 0;
}

/// What a patch's pixels border on, down and up its image columns (cameras held about level) from
/// each column's lowest and highest pixel. open_below: the share of what is seen 0.12-0.3 m below
/// the lower edge that lies far behind it (open space: legs, the floor under a table) rather than
/// at its depth (a box's front under its top); what lies in front (an occluder) does not count;
/// NaN with fewer than 20 such pixels. top_hidden, bottom_hidden: along most of the edge, the image
/// ends there (within 12 pixels of its border: the normals' window leaves a rim of bad normals
/// that no patch takes) or the depth steps in front beyond it (depth_step: an occluder).
/// far_hidden (level patches): so along the upper edge in the image, the far one, where what
/// stands on the patch (rising from its plane) hides it as well.
/// side_cut: the share of its rows that end on the image's left or right rim. stands_out (upright
/// patches): the share of its rows' ends off the rim beyond which the depth steps behind (a front
/// before its wall) rather than in front (an occluder) or not at all (the wall it is part of, a
/// door's frame, its own side at a convex corner); NaN with fewer than 10 such ends. Points within
/// half the growth's tolerance of the plane (through c) are its own.
void edges(const Cloud& cloud, const std::vector<int>& pixels, double a, bool upright, const Eigen::Vector3d& c,
           double epsilon, shapes::Patch& patch) {
  constexpr int rim = 12;
  const int W = cloud.cols(), H = cloud.rows();
  // each column's lowest and highest pixel, each row's first and last
  std::vector<int> bottom(std::size_t(W), -1), top(std::size_t(W), H), left(std::size_t(H), W), right(std::size_t(H), -1);
  for (int i : pixels) {
    const int u = i % W, v = i / W;
    bottom[std::size_t(u)] = std::max(bottom[std::size_t(u)], v), top[std::size_t(u)] = std::min(top[std::size_t(u)], v);
    left[std::size_t(v)] = std::min(left[std::size_t(v)], u), right[std::size_t(v)] = std::max(right[std::size_t(v)], u);
  }
  int open = 0, closed = 0;
  int hidden[2] = {0, 0}, seen[2] = {0, 0};  // above, below
  for (int u = 0; u < W; ++u) {
    if (bottom[std::size_t(u)] < 0) continue;
    const int vb = bottom[std::size_t(u)], vt = top[std::size_t(u)];
    const double z = cloud.ptr(vb, u)[2], s = z * a;  // a pixel's size there
    const double margin = far_step(z);
    const int v0 = vb + int(std::ceil(0.12 / s)), v1 = vb + int(std::ceil(0.3 / s));
    for (int v = v0; v <= std::min(v1, H - 1); ++v) {
      const float* q = cloud.ptr(v, u);
      if (!valid_point(q)) continue;
      if (q[2] > z + margin) ++open;
      else if (q[2] >= z - margin) ++closed;
    }
    if (!upright) {  // a level patch's far edge
      if (vt < rim) {
        ++seen[0], ++hidden[0];
        continue;
      }
      ++seen[0], hidden[0] += depth_step(cloud, vt, u, -1, 0, rim, patch.normal, c, epsilon, true) < 0;
      continue;
    }
    // what lies beyond each edge: an occluder in front hides it
    for (const int side : {0, 1}) {
      const int edge = side == 0 ? vt : vb, dir = side == 0 ? -1 : 1;
      if (side == 0 ? edge < rim : edge >= H - rim) {
        ++seen[side], ++hidden[side];
        continue;
      }
      ++seen[side];
      hidden[side] += depth_step(cloud, edge, u, dir, 0, rim, patch.normal, c, epsilon) < 0;
    }
  }
  // the rows whose first or last pixel lies on the image's side rim: the patch's width is cut there
  int rows = 0, cut = 0, ends = 0, out = 0;
  for (int v = 0; v < H; ++v) {
    const int l = left[std::size_t(v)], r = right[std::size_t(v)];
    if (r < 0) continue;
    ++rows, cut += l < rim || r >= W - rim;
    if (!upright) continue;
    for (const int side : {0, 1}) {
      const int edge = side == 0 ? l : r, dir = side == 0 ? -1 : 1;
      if (side == 0 ? edge < rim : edge >= W - rim) continue;
      ++ends, out += depth_step(cloud, v, edge, 0, dir, rim, patch.normal, c, epsilon) > 0;
    }
  }
  patch.side_cut = rows ? double(cut) / rows : 0.0;
  patch.stands_out = ends >= 10 ? double(out) / ends : std::nan("");
  patch.open_below = open + closed >= 20 ? double(open) / (open + closed) : std::nan("");
  const bool hid[2] = {seen[0] > 0 && 2 * hidden[0] >= seen[0], seen[1] > 0 && 2 * hidden[1] >= seen[1]};
  if (upright) patch.top_hidden = hid[0], patch.bottom_hidden = hid[1];
  else patch.far_hidden = hid[0];
}

/// A region grown, before it is described: its plane (normal through c), pixels, seen area and
/// the sum of its pixels' squared distances to the plane.
struct Found {
  Eigen::Vector3d normal, c;
  std::vector<int> pixels;
  double area, sq;
  bool takes_rim;  ///< upright with gravity known, or any without it
};

/// Level regions (grown about up itself: their normal is up) at one height that touch (points of
/// both within `gap` metres, over a sample of at most ~400 of each) are one surface found in
/// pieces: a table top seen at a grazing angle, where the rows' depth steps part the grid's cells.
/// Each such set is merged into the piece grown first (the order of growth kept), its pixels, area
/// and squared residuals summed, its centre their mean; owner follows. Heights agree within the
/// growth's tolerance at the nearer piece's depth.
void join_level_pieces(const Cloud& cloud, const PatchOptions& o, const Eigen::Vector3d& up, double gap,
                       std::vector<int>& owner, std::vector<Found>& found) {
  const auto is_level = [&](const Found& f) { return f.normal.dot(up) > 1 - 1e-9; };
  const auto point = [&](int i) {
    const float* q = cloud.data() + 3 * std::size_t(i);
    return Eigen::Vector3d(q[0], q[1], q[2]);
  };
  // a sample of each level piece's pixels (at most ~400) for the distance between pieces
  std::vector<std::vector<Eigen::Vector3d>> sample(found.size());
  for (std::size_t k = 0; k < found.size(); ++k) {
    if (!is_level(found[k])) continue;
    const std::size_t step = std::max<std::size_t>(1, found[k].pixels.size() / 400);
    for (std::size_t i = 0; i < found[k].pixels.size(); i += step) sample[k].push_back(point(found[k].pixels[i]));
  }
  const auto touch = [&](std::size_t a, std::size_t b) {
    for (const auto& x : sample[a])
      for (const auto& y : sample[b])
        if ((x - y).norm() < gap) return true;
    return false;
  };
  std::vector<int> into(found.size(), -1);
  for (std::size_t a = 0; a < found.size(); ++a) {
    if (!is_level(found[a]) || into[a] >= 0) continue;
    for (std::size_t b = a + 1; b < found.size(); ++b) {
      if (!is_level(found[b]) || into[b] >= 0) continue;
      const double z = std::min(found[a].c.z(), found[b].c.z());
      if (std::abs(up.dot(found[a].c - found[b].c)) > plane_tolerance(o.epsilon, z) || !touch(a, b)) continue;
      Found& f = found[a];
      const double na = double(f.pixels.size()), nb = double(found[b].pixels.size());
      f.c = (f.c * na + found[b].c * nb) / (na + nb);
      f.pixels.insert(f.pixels.end(), found[b].pixels.begin(), found[b].pixels.end());
      f.area += found[b].area, f.sq += found[b].sq;
      sample[a].insert(sample[a].end(), sample[b].begin(), sample[b].end());
      into[b] = int(a);
    }
  }
  std::vector<int> index(found.size(), -1);
  std::vector<Found> kept;
  for (std::size_t k = 0; k < found.size(); ++k)
    if (into[k] < 0) index[k] = int(kept.size()), kept.push_back(std::move(found[k]));
  for (int& w : owner)
    if (w >= 0) w = index[std::size_t(into[std::size_t(w)] >= 0 ? into[std::size_t(w)] : w)];
  found = std::move(kept);
}

/// PatchOptions::rim: rings of free pixels beside the patches that take a rim, o.rim of them, each
/// pixel joining the neighbouring (4-connected) one whose plane lies nearest to it, within half the growth's
/// tolerance and without a depth jump from that neighbour. Ring by ring, so that two patches that
/// meet (a wall and the floor at its foot) share their rims by distance, not by order.
void give_back_the_rim(const Cloud& cloud, const PatchOptions& o, double a, std::vector<int>& owner,
                       std::vector<Found>& found) {
  const int W = cloud.cols(), H = cloud.rows();
  std::vector<std::pair<int, int>> joins;  // (pixel, patch) of one ring
  std::vector<int> frontier, next;
  for (int i = 0; i < W * H; ++i)
    if (owner[std::size_t(i)] >= 0 && found[std::size_t(owner[std::size_t(i)])].takes_rim) frontier.push_back(i);
  std::vector<std::uint8_t> queued(std::size_t(W) * std::size_t(H), 0);
  for (int ring = 0; ring < o.rim && !frontier.empty(); ++ring) {
    joins.clear();
    // the free neighbours of the last ring
    next.clear();
    for (int i : frontier) {
      const int u = i % W, v = i / W;
      for (const auto& d : {std::array<int, 2>{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int uu = u + d[0], vv = v + d[1];
        if (uu < 0 || uu >= W || vv < 0 || vv >= H) continue;
        const int j = vv * W + uu;
        if (owner[std::size_t(j)] >= 0 || queued[std::size_t(j)] || !valid_point(cloud.ptr(vv, uu))) continue;
        queued[std::size_t(j)] = 1;
        next.push_back(j);
      }
    }
    for (int j : next) {
      queued[std::size_t(j)] = 0;
      const int u = j % W, v = j / W;
      const float* q = cloud.ptr(v, u);
      const Eigen::Vector3d x(q[0], q[1], q[2]);
      int best = -1;
      double best_dist = 0.5 * plane_tolerance(o.epsilon, x.z());
      for (const auto& d : {std::array<int, 2>{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int uu = u + d[0], vv = v + d[1];
        if (uu < 0 || uu >= W || vv < 0 || vv >= H) continue;
        const int k = owner[std::size_t(vv * W + uu)];
        if (k < 0 || !found[std::size_t(k)].takes_rim || std::abs(cloud.ptr(vv, uu)[2] - q[2]) > o.depth_jump * q[2]) continue;
        const double dist = std::abs(found[std::size_t(k)].normal.dot(x - found[std::size_t(k)].c));
        if (dist <= best_dist) best = k, best_dist = dist;
      }
      if (best >= 0) joins.emplace_back(j, best);
    }
    frontier.clear();
    for (const auto& [j, k] : joins) {
      owner[std::size_t(j)] = k;
      Found& f = found[std::size_t(k)];
      const float* q = cloud.data() + 3 * std::size_t(j);
      const Eigen::Vector3d x(q[0], q[1], q[2]);
      const double dist = f.normal.dot(x - f.c);
      f.pixels.push_back(j), f.sq += dist * dist, f.area += footprint(x, f.normal, a);
      frontier.push_back(j);
    }
  }
}

}  // namespace

std::vector<Segment> planar_patches(const Cloud& cloud, const NormalMap& normals, const PatchOptions& o,
                                    const Eigen::Vector3d* up, const ColorImage* color) {
  if (!cloud.same_size(normals))
    throw InputError("planar patches: cloud " + std::to_string(cloud.cols()) + "x" + std::to_string(cloud.rows()) +
                     " and normals " + std::to_string(normals.cols()) + "x" + std::to_string(normals.rows()) +
                     " differ in size");
  if (color && !color->empty() && !color->same_size(cloud))
    throw InputError("planar patches: the colour image's size differs from the cloud's");
  if (o.step < 1) throw InputError("planar patches: step must be at least 1");
  const Grid g(cloud, normals, o.step);
  const int cells = g.gw * g.gh;
  const double cos_max = std::cos(o.max_angle_deg * detail::kDeg);
  const auto tol = [&](double z) { return plane_tolerance(o.epsilon, z); };
  std::vector<int> label(std::size_t(cells), -1);  // 1: a cell in a region; -1 free
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(cells));
  for (int k = 0; k < cells; ++k) valid[std::size_t(k)] = g.valid(k);

  // each cell's mean colour over its block (RGB in [0, 1]), where a colour image is given: growth
  // does not cross a colour edge (a door in its wall, a seat's cushion on its frame)
  const bool by_colour = color && !color->empty() && o.colour_edge > 0;
  std::vector<Eigen::Vector3f> cell_colour(by_colour ? std::size_t(cells) : 0);
  if (by_colour)
    for (int k = 0; k < cells; ++k) {
      const int u0 = (k % g.gw) * o.step, v0 = (k / g.gw) * o.step;
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      int count = 0;
      for (int v = v0; v < std::min(cloud.rows(), v0 + o.step); ++v)
        for (int u = u0; u < std::min(cloud.cols(), u0 + o.step); ++u, ++count) {
          const std::uint8_t* c = color->ptr(v, u);
          sum += Eigen::Vector3f(c[0], c[1], c[2]) / 255.f;
        }
      cell_colour[std::size_t(k)] = sum / float(std::max(1, count));
    }
  // cells on a colour edge at the pixel level (a step of more than colour_edge between neighbouring
  // pixels of the block or into the next): along a slanted door edge their means blend door, wall
  // and the dark gap between them into a ramp of steps each below colour_edge. Upright growth takes
  // them, but leaves them only for a cell of the colour it had before it entered them (`before`:
  // the last cell off an edge on its way), so it does not walk down the ramp into the door.
  std::vector<std::uint8_t> on_line(by_colour ? std::size_t(cells) : 0, 0);
  if (by_colour) {
    const float line = float(o.colour_edge);
    const auto rgb = [&](int v, int u) -> Eigen::Vector3f {
      const std::uint8_t* c = color->ptr(v, u);
      return Eigen::Vector3f(c[0], c[1], c[2]) / 255.f;
    };
    for (int k = 0; k < cells; ++k) {
      const int u0 = (k % g.gw) * o.step, v0 = (k / g.gw) * o.step;
      bool hit = false;
      for (int v = v0; v < std::min(cloud.rows(), v0 + o.step) && !hit; ++v)
        for (int u = u0; u < std::min(cloud.cols(), u0 + o.step) && !hit; ++u) {
          const Eigen::Vector3f c = rgb(v, u);
          hit = (u + 1 < cloud.cols() && (rgb(v, u + 1) - c).norm() > line) ||
                (v + 1 < cloud.rows() && (rgb(v + 1, u) - c).norm() > line);
        }
      on_line[std::size_t(k)] = hit;
    }
  }
  // a step from cell a to b crosses a colour edge when b differs from a, or from the cell behind
  // a on the same line: an edge blurred over two cells (a door's frame drawn in) is a step too,
  // a wall's shading over three cells is not
  const auto colour_edge = [&](int a, int b) {
    if (!by_colour) return false;
    const auto differ = [&](int x, int y) {
      return (cell_colour[std::size_t(x)] - cell_colour[std::size_t(y)]).norm() > o.colour_edge;
    };
    if (differ(a, b)) return true;
    const int du = b % g.gw - a % g.gw, dv = b / g.gw - a / g.gw;
    const int bu = a % g.gw - du, bv = a / g.gw - dv;
    return bu >= 0 && bu < g.gw && bv >= 0 && bv < g.gh && differ(bv * g.gw + bu, b);
  };
  // With gravity and level_deg, level surfaces (seats, table tops, the floor) are grown first,
  // about the plane normal to up through their points' mean height: their normals are the worst
  // of a frame (seen at grazing angles, small, their depth in steps), but their heights are
  // measured well (a depth error along the ray moves a point up only by its share of up), and
  // their normals need only lean towards up (not a back, a wall or a door).
  const Eigen::Vector3d upn = up ? Eigen::Vector3d(up->normalized()) : Eigen::Vector3d::Zero();
  // with gravity: a plane that stands within upright_deg of vertical (a wall, a door, a back)
  const double sin_upright = std::sin(o.upright_deg * detail::kDeg);
  const auto is_upright = [&](const Eigen::Vector3d& n) { return up && std::abs(n.dot(upn)) <= sin_upright; };
  const double cos_level = std::cos(o.level_deg * detail::kDeg), cos_seed = std::cos(0.5 * o.level_deg * detail::kDeg);
  // whether x, `dist` from a patch's plane, lies on it
  const auto on_plane = [&](const Eigen::Vector3d& x, double dist, bool level) {
    const double t = level ? tol(x.z()) * std::max(0.25, std::abs(upn.dot(x.normalized()))) : tol(x.z());
    return std::abs(dist) <= t;
  };
  // Grows the free cells connected to `seed` that lie on the plane of those gathered so far
  // (starting from n through c; a level one's normal stays up), refitting it as the region doubles.
  std::vector<int> queue;
  std::vector<std::uint8_t> seen(std::size_t(cells), 0);
  std::vector<int> before(by_colour ? std::size_t(cells) : 0);
  const auto grow = [&](int seed, Eigen::Vector3d n, Eigen::Vector3d c, PlaneSums& sums, bool level) {
    queue.assign(1, seed);
    seen[std::size_t(seed)] = 1;
    if (by_colour) before[std::size_t(seed)] = seed;
    sums = PlaneSums{};
    sums.ref = g.p(seed);
    std::size_t next_fit = 128;  // the first refits wait for an extent that outweighs the noise
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const int k = queue[h];
      const Eigen::Vector3d pk = g.p(k);
      sums.add(pk);
      if (sums.n >= next_fit) n = level ? n : sums.normal(n), c = sums.centroid(), next_fit *= 2;
      // 8-neighbours and the cells two away along the axes: the growth steps over the small
      // holes that depth leaves on surfaces seen at grazing angles (a table top from 3 m)
      const int gu = k % g.gw, gv = k / g.gw;
      const int nb[12][2] = {{gu - 1, gv},     {gu + 1, gv},     {gu, gv - 1},     {gu, gv + 1},
                             {gu - 1, gv - 1}, {gu + 1, gv - 1}, {gu - 1, gv + 1}, {gu + 1, gv + 1},
                             {gu - 2, gv},     {gu + 2, gv},     {gu, gv - 2},     {gu, gv + 2}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= g.gw || q[1] < 0 || q[1] >= g.gh) continue;
        const int j = q[1] * g.gw + q[0];
        if (seen[std::size_t(j)] || !valid[std::size_t(j)] || label[std::size_t(j)] >= 0) continue;
        const Eigen::Vector3d pj = g.p(j);
        if (std::abs(pj.z() - pk.z()) > o.depth_jump * pk.z() || colour_edge(k, j)) continue;
        if (by_colour && !level && before[std::size_t(k)] != k && !on_line[std::size_t(j)] &&
            (cell_colour[std::size_t(before[std::size_t(k)])] - cell_colour[std::size_t(j)]).norm() > o.colour_edge)
          continue;
        if (!on_plane(pj, n.dot(pj - c), level) || g.n(j).dot(n) < (level ? cos_level : cos_max)) continue;
        seen[std::size_t(j)] = 1;
        if (by_colour) before[std::size_t(j)] = on_line[std::size_t(j)] ? before[std::size_t(k)] : j;
        queue.push_back(j);
      }
    }
    for (int k : queue) seen[std::size_t(k)] = 0;
    return queue;
  };

  const double a = angular_pixel(cloud);
  const int min_cells = std::max(3, o.min_pixels / (o.step * o.step));
  std::vector<std::uint8_t> taken(std::size_t(cloud.rows()) * std::size_t(cloud.cols()), 0);
  // seeds flattest first (as PCL's region growing orders them by curvature): a cell whose
  // normal agrees with those two cells away on all four sides; a seed on an edge or in clutter
  // would start a plane that cuts through its neighbours' patches
  std::vector<std::pair<float, int>> seeds;
  seeds.reserve(std::size_t(cells));
  for (int k = 0; k < cells; ++k) {
    if (!valid[std::size_t(k)]) continue;
    const int gu = k % g.gw, gv = k / g.gw;
    double flat = 0;
    const Eigen::Vector3d nk = g.n(k);
    for (const auto& q : {std::array<int, 2>{gu - 2, gv}, {gu + 2, gv}, {gu, gv - 2}, {gu, gv + 2}}) {
      const int j = q[1] * g.gw + q[0];
      flat += q[0] >= 0 && q[0] < g.gw && q[1] >= 0 && q[1] < g.gh && valid[std::size_t(j)] ? nk.dot(g.n(j)) : -1.0;
    }
    seeds.emplace_back(-float(flat), k);
  }
  std::stable_sort(seeds.begin(), seeds.end());
  std::vector<Found> found;
  std::vector<int> owner(std::size_t(cloud.rows()) * std::size_t(cloud.cols()), -1);  // a pixel's patch
  std::vector<std::uint8_t> tried(std::size_t(cells), 0), band(std::size_t(cells), 0);
  // a region's thinner side across up: sqrt(12) times the smaller spread of its cells (a rectangle's)
  const auto level_width = [&](const std::vector<int>& region) {
    const Eigen::Vector3d e0 = upn.unitOrthogonal(), e1 = upn.cross(e0);
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (int k : region) {
      const Eigen::Vector3d x = g.p(k);
      const Eigen::Vector2d q(e0.dot(x), e1.dot(x));
      mean += q, cov += q * q.transpose();
    }
    const double n = double(region.size());
    mean /= n;
    cov = cov / n - mean * mean.transpose();
    return std::sqrt(12.0 * std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues()(0)));
  };
  for (const bool level : {true, false})
  for (const auto& [flatness, seed] : seeds) {
    if (label[std::size_t(seed)] >= 0 || tried[std::size_t(seed)] || (level && band[std::size_t(seed)])) continue;
    if (level && (!up || !(o.level_deg > 0) || g.n(seed).dot(upn) < cos_seed)) continue;
    // grown twice: from the seed's normal (up for a level one), then from the plane that gathered
    // (a noisy seed normal stops the first growth early)
    PlaneSums sums;
    const Eigen::Vector3d n0 = level ? upn : g.n(seed);
    std::vector<int> region = grow(seed, n0, g.p(seed), sums, level);
    if (int(region.size()) < min_cells) {
      if (!level) for (int k : region) tried[std::size_t(k)] = 1;  // none of them starts a larger one
      continue;
    }
    const Eigen::Vector3d n1 = level ? upn : sums.normal(g.n(seed)), c1 = sums.centroid();
    region = grow(seed, n1, c1, sums, level);
    if (int(region.size()) < min_cells) continue;
    if (level && level_width(region) < o.level_min_width) {
      for (int k : region) band[std::size_t(k)] = 1;  // seeds no other level region
      continue;
    }
    for (int k : region) label[std::size_t(k)] = 1;

    const Eigen::Vector3d normal = level ? upn : sums.normal(n1);
    const Eigen::Vector3d c = sums.centroid();
    // every pixel of the region's blocks on its plane; the seen area: theirs and that of the holes
    // in depth in their blocks (a surface whose depth is sparse covers its blocks all the same)
    std::vector<int> pixels;
    double area = 0, sq = 0;
    const int H = cloud.rows(), W = cloud.cols();
    for (int k : region) {
      const int u0 = (k % g.gw) * o.step, v0 = (k / g.gw) * o.step;
      const int bw = std::min(W, u0 + o.step) - u0, bh = std::min(H, v0 + o.step) - v0;
      double block = 0;  // the footprint of the block's pixels on the plane
      int on = 0, holes = 0;
      for (int v = v0; v < v0 + bh; ++v)
        for (int u = u0; u < u0 + bw; ++u) {
          const int i = v * W + u;
          const float* q = cloud.ptr(v, u);
          if (!valid_point(q)) ++holes;
          if (taken[std::size_t(i)] || !valid_point(q)) continue;
          const Eigen::Vector3d x(q[0], q[1], q[2]);
          const double dist = normal.dot(x - c);
          if (!on_plane(x, dist, level)) continue;
          taken[std::size_t(i)] = 1;
          pixels.push_back(i);
          sq += dist * dist;
          block += footprint(x, normal, a);
          ++on;
        }
      if (on) area += block * (1.0 + double(holes) / on);
    }
    if (int(pixels.size()) < o.min_pixels || area < o.min_area) continue;
    {
      std::vector<double> z;
      z.reserve(pixels.size());
      for (int i : pixels) z.push_back(cloud.data()[3 * std::size_t(i) + 2]);
      if (detail::quantile(z, 0.5) > o.max_depth) continue;
    }
    for (int i : pixels) owner[std::size_t(i)] = int(found.size());
    const bool takes_rim = !up || is_upright(normal);
    found.push_back({normal, c, std::move(pixels), area, sq, takes_rim});
  }
  if (up && o.level_deg > 0) join_level_pieces(cloud, o, upn, 0.05, owner, found);
  if (o.rim > 0) give_back_the_rim(cloud, o, a, owner, found);
  std::vector<Segment> out;
  for (Found& f : found) {
    shapes::Patch patch;
    patch.normal = f.normal;
    const Eigen::Vector3d& c = f.c;
    std::vector<int>& pixels = f.pixels;
    const double area = f.area, sq = f.sq;
    // the rectangle: upright patches along gravity, the others along their points' main direction
    std::vector<Eigen::Vector3d> pts;
    pts.reserve(pixels.size());
    for (int i : pixels) {
      const float* q = cloud.data() + 3 * std::size_t(i);
      pts.emplace_back(q[0], q[1], q[2]);
    }
    const bool upright = is_upright(patch.normal);
    if (upright) {
      patch.u_axis = shapes::unit_across(upn.cross(patch.normal), patch.normal);
    } else {
      const Eigen::Vector3d e0 = patch.normal.unitOrthogonal(), e1 = patch.normal.cross(e0);
      Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
      for (const auto& x : pts) {
        const Eigen::Vector2d q(e0.dot(x - c), e1.dot(x - c));
        cov += q * q.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
      const Eigen::Vector2d m = es.eigenvectors().col(1);
      patch.u_axis = (m.x() * e0 + m.y() * e1).normalized();
    }
    if (up) edges(cloud, pixels, a, upright, c, o.epsilon, patch);
    const Eigen::Vector3d v_axis = patch.normal.cross(patch.u_axis).normalized();
    std::vector<double> su, sv, w;
    su.reserve(pts.size()), sv.reserve(pts.size()), w.reserve(pts.size());
    for (const auto& x : pts)
      su.push_back(patch.u_axis.dot(x - c)), sv.push_back(v_axis.dot(x - c)), w.push_back(footprint(x, patch.normal, a));
    // robust to stray points: the 2nd to 98th percentiles of the area (each pixel weighed by its
    // footprint), widened to the whole side as they are for an area covered evenly; by pixel count,
    // a top seen at a grazing angle was cut short at its far end, where a pixel covers the most
    constexpr double q = 0.02;
    const auto [u0, u1] = detail::weighted_quantiles(su, w, q);
    const auto [v0, v1] = detail::weighted_quantiles(sv, w, q);
    patch.size_u = (u1 - u0) / (1 - 2 * q), patch.size_v = (v1 - v0) / (1 - 2 * q), patch.area = area;
    patch.point = c + patch.u_axis * (u0 + u1) / 2 + v_axis * (v0 + v1) / 2;
    patch.canonical();
    Segment s(patch);
    s.inliers = pixels.size();
    s.residual = std::sqrt(sq / double(pixels.size()));
    s.pixels = std::move(pixels);  // in cell order: sorted below
    std::sort(s.pixels.begin(), s.pixels.end());
    detail::set_color(s, color);
    out.push_back(std::move(s));
  }
  std::stable_sort(out.begin(), out.end(), [](const Segment& x, const Segment& y) {
    return x.as<shapes::Patch>().area > y.as<shapes::Patch>().area;
  });
  // flush: an upright patch whose centre lies within 1 cm of a larger upright one's plane,
  // parallel to it within 5 degrees: a piece of that wall beside a door or a cabinet, parted from
  // the rest by what stands before it (rendered tuning rooms 9500-9539: such pieces 0-2 mm off
  // their wall's plane, closed doors 23-47 mm)
  if (up) {
    const double cos_parallel = std::cos(5 * detail::kDeg);
    for (std::size_t i = 1; i < out.size(); ++i) {
      auto& p = out[i].as<shapes::Patch>();
      if (!is_upright(p.normal)) continue;
      for (std::size_t j = 0; j < i && !p.flush; ++j) {
        const auto& q = out[j].as<shapes::Patch>();
        p.flush = is_upright(q.normal) && q.area > p.area && std::abs(q.normal.dot(p.normal)) >= cos_parallel &&
                  std::abs(q.normal.dot(p.point - q.point)) < 0.01;
      }
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].id = int(i);
  return out;
}

}  // namespace mereo::features
