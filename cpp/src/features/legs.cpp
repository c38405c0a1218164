// The legs under level patches (mereo/features/legs.hpp).
#include "mereo/features/legs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "features/pixels.hpp"
#include "mereo/core/error.hpp"
#include "mereo/shapes/cylinder.hpp"
#include "mereo/shapes/patch.hpp"

namespace mereo::features {
namespace {

/// A point under some patch: its pixel, height above the floor and position.
struct Low {
  int pixel;
  float height;
  Eigen::Vector3d x;
};

/// One cell's points on the grid under a patch.
struct Cell {
  std::vector<int> points;  // indices into the Low list
  float lo = INFINITY, hi = -INFINITY;
  int above = 0;            // points 5-20 cm above the patch
};

/// Points 5-20 cm above the patch over which a leg ends, where a higher patch's rectangle holds
/// it too: a leg of its own ends under it; a table's leg beside a chair's seat rises on past it,
/// alone, where a chair's back over its rear legs spreads sideways along the seat's edge.
constexpr double kAboveFrom = 0.05, kAboveTo = 0.2;

}  // namespace

std::vector<const shapes::Patch*> leg_tops(const std::vector<Segment>& segments, const Eigen::Vector3d& up_in,
                                           double floor_d, const LegOptions& o) {
  const Eigen::Vector3d up = up_in.normalized();
  const auto height = [&](const Eigen::Vector3d& x) { return up.dot(x) + floor_d; };
  std::vector<const shapes::Patch*> tops;
  for (const auto& s : segments)
    if (const auto* p = s.get_if<shapes::Patch>()) {
      const double h = height(p->point);
      if (h >= o.min_top && h <= o.max_top && std::abs(p->normal.normalized().dot(up)) >= std::cos(o.max_tilt_deg * detail::kDeg))
        tops.push_back(p);
    }
  std::stable_sort(tops.begin(), tops.end(), [&](const auto* a, const auto* b) { return height(a->point) > height(b->point); });
  return tops;
}

bool leg_shaped(double width, double lo, double hi, double h, const LegOptions& o) {
  return width <= o.max_width && hi - lo >= o.min_span * (h - o.top_clear - o.floor_clear) && hi >= h - o.reach;
}

std::vector<Segment> find_legs(const Cloud& cloud, const std::vector<Segment>& segments, const Eigen::Vector3d& up_in,
                               double floor_d, const LegOptions& o) {
  if (!(up_in.norm() > 0) || !std::isfinite(floor_d)) throw InputError("legs: the floor's normal and offset must be finite");
  if (!(o.cell > 0) || o.step < 1) throw InputError("legs: cell must be positive and step at least 1");
  const Eigen::Vector3d up = up_in.normalized();
  const auto height = [&](const Eigen::Vector3d& x) { return up.dot(x) + floor_d; };

  const std::vector<const shapes::Patch*> tops = leg_tops(segments, up, floor_d, o);
  std::vector<Segment> out;
  if (tops.empty()) return out;

  // every point that could be under one of them, scanned once
  const double highest = height(tops.front()->point);
  std::vector<Low> low;
  for (int v = 0; v < cloud.rows(); v += o.step)
    for (int u = 0; u < cloud.cols(); u += o.step) {
      const float* q = cloud.ptr(v, u);
      if (!valid_point(q)) continue;
      const Eigen::Vector3d x(q[0], q[1], q[2]);
      const double h = height(x);
      if (h >= o.floor_clear && h <= highest + kAboveTo) low.push_back({v * cloud.cols() + u, float(h), x});
    }
  std::vector<std::uint8_t> taken(low.size(), 0);
  struct Done {  // a patch looked under: its horizontal rectangle (grown by the margin)
    Eigen::Vector3d point, eu, ev;
    double hu, hv;
  };
  std::vector<Done> done;

  for (const shapes::Patch* top : tops) {
    const double h = height(top->point);
    // the rectangle's axes made horizontal
    Eigen::Vector3d eu = top->u_axis - up * up.dot(top->u_axis);
    if (eu.norm() < 1e-6) continue;
    eu.normalize();
    const Eigen::Vector3d ev = up.cross(eu);
    const double hu = 0.5 * top->size_u + o.margin, hv = 0.5 * top->size_v + o.margin;
    const int nu = std::min(400, int(std::ceil(2 * hu / o.cell))), nv = std::min(400, int(std::ceil(2 * hv / o.cell)));
    std::vector<Cell> grid(std::size_t(nu) * std::size_t(nv));
    for (std::size_t k = 0; k < low.size(); ++k) {
      const bool above = low[k].height > h + kAboveFrom && low[k].height <= h + kAboveTo;
      if (taken[k] || (low[k].height > h - o.top_clear && !above)) continue;
      const Eigen::Vector3d d = low[k].x - top->point;
      const double a = eu.dot(d) + hu, b = ev.dot(d) + hv;
      const int iu = int(a / o.cell), iv = int(b / o.cell);
      if (a < 0 || b < 0 || iu >= nu || iv >= nv) continue;
      Cell& c = grid[std::size_t(iv) * std::size_t(nu) + std::size_t(iu)];
      if (above) {
        ++c.above;
        continue;
      }
      c.points.push_back(int(k)), c.lo = std::min(c.lo, low[k].height), c.hi = std::max(c.hi, low[k].height);
    }
    // 8-connected groups of occupied cells
    std::vector<int> group(grid.size(), -1), stack;
    for (int start = 0; start < int(grid.size()); ++start) {
      if (grid[std::size_t(start)].points.empty() || group[std::size_t(start)] >= 0) continue;
      std::vector<int> cells;
      group[std::size_t(start)] = start, stack.assign(1, start);
      while (!stack.empty()) {
        const int c = stack.back();
        stack.pop_back();
        cells.push_back(c);
        const int cu = c % nu, cv = c / nu;
        for (int dv = -1; dv <= 1; ++dv)
          for (int du = -1; du <= 1; ++du) {
            const int uu = cu + du, vv = cv + dv;
            if (uu < 0 || vv < 0 || uu >= nu || vv >= nv) continue;
            const int n = vv * nu + uu;
            if (grid[std::size_t(n)].points.empty() || group[std::size_t(n)] >= 0) continue;
            group[std::size_t(n)] = start, stack.push_back(n);
          }
      }
      int u0 = nu, u1 = -1, v0 = nv, v1 = -1;
      float lo = INFINITY, hi = -INFINITY;
      std::size_t count = 0;
      for (int c : cells) {
        u0 = std::min(u0, c % nu), u1 = std::max(u1, c % nu), v0 = std::min(v0, c / nu), v1 = std::max(v1, c / nu);
        lo = std::min(lo, grid[std::size_t(c)].lo), hi = std::max(hi, grid[std::size_t(c)].hi);
        count += grid[std::size_t(c)].points.size();
      }
      const double width = o.cell * std::max(u1 - u0 + 1, v1 - v0 + 1);
      if (int(count) < o.min_points || !leg_shaped(width, lo, hi, h, o)) continue;
      // under a higher patch too, and rising on past this one, alone: what is above its cells and
      // what is 2-4 cells around them
      const Eigen::Vector3d at = top->point + eu * ((u0 + u1 + 1) * 0.5 * o.cell - hu) + ev * ((v0 + v1 + 1) * 0.5 * o.cell - hv);
      bool under_higher = false;
      for (const Done& q : done)
        under_higher = under_higher || (std::abs(q.eu.dot(at - q.point)) <= q.hu && std::abs(q.ev.dot(at - q.point)) <= q.hv);
      int over = 0, around = 0;
      for (int cv = std::max(0, v0 - 4); cv <= std::min(nv - 1, v1 + 4); ++cv)
        for (int cu = std::max(0, u0 - 4); cu <= std::min(nu - 1, u1 + 4); ++cu) {
          const int ring = std::max({u0 - cu, cu - u1, v0 - cv, cv - v1, 0});
          const int n = grid[std::size_t(cv) * std::size_t(nu) + std::size_t(cu)].above;
          if (ring == 0) over += n;
          else if (ring >= 2) around += n;
        }
      if (under_higher && over >= o.min_points && 4 * around < over) continue;
      // the leg: its points' horizontal centre, the span seen
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      Segment s;
      for (int c : cells)
        for (int k : grid[std::size_t(c)].points) {
          mean += low[std::size_t(k)].x - up * up.dot(low[std::size_t(k)].x);
          s.pixels.push_back(low[std::size_t(k)].pixel);
          taken[std::size_t(k)] = 1;
        }
      mean /= double(count);
      // the rest of a leg already found under another patch (a seat found in two pieces): one leg
      auto same = std::find_if(out.begin(), out.end(), [&](const Segment& l) {
        const auto& c = l.as<shapes::Cylinder>();
        return (c.point - up * up.dot(c.point) - mean).norm() <= 0.5 * o.max_width;
      });
      if (same != out.end()) {
        auto& c = std::get<shapes::Cylinder>(same->shape);
        const double h0 = height(c.point);
        lo = std::min(lo, float(h0 - 0.5 * c.height)), hi = std::max(hi, float(h0 + 0.5 * c.height));
        c.point += up * (0.5 * (lo + hi) - h0), c.height = hi - lo;
        same->pixels.insert(same->pixels.end(), s.pixels.begin(), s.pixels.end());
        std::sort(same->pixels.begin(), same->pixels.end());
        same->inliers = same->pixels.size();
        continue;
      }
      shapes::Cylinder leg;
      leg.axis = up;
      leg.point = mean + up * (0.5 * (lo + hi) - floor_d);
      leg.height = hi - lo;
      leg.radius = std::max(0.01, 0.5 * width);
      double sq = 0;
      for (int c : cells)
        for (int k : grid[std::size_t(c)].points) {
          const double r = leg.signed_distance(low[std::size_t(k)].x);
          sq += r * r;
        }
      s.shape = leg;
      s.inliers = s.pixels.size();
      s.residual = std::sqrt(sq / double(count));
      std::sort(s.pixels.begin(), s.pixels.end());
      out.push_back(std::move(s));
    }
    done.push_back({top->point, eu, ev, hu, hv});
  }
  return out;
}

}  // namespace mereo::features
