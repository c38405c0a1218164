// Internal: the organized frame as the RANSAC search and the handle search read it (Pixels), and
// the steps that turn a candidate's pixels into a segment. See features/primitives.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "features/fit.hpp"
#include "mereo/core/image.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/features/primitives.hpp"

namespace mereo::features::detail {

constexpr double kDeg = M_PI / 180.0;

/// The q-quantile of v (reordered), 0 for none.
inline double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const auto k = std::size_t(q * double(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

/// The weighted q- and (1 - q)-quantiles of x (weights w), read off a histogram of 4096 bins over
/// its range, interpolated within a bin: within a bin of the sorted answer, in time linear in the
/// points (a floor holds 100 000 pixels).
inline std::pair<double, double> weighted_quantiles(const std::vector<double>& x, const std::vector<double>& w, double q) {
  if (x.empty()) return {0.0, 0.0};
  const auto [mn, mx] = std::minmax_element(x.begin(), x.end());
  const double lo = *mn, hi = *mx;
  if (!(hi > lo)) return {lo, hi};
  constexpr int bins = 4096;
  const double scale = bins / (hi - lo);
  std::vector<double> h(bins, 0.0);
  double total = 0;
  for (std::size_t i = 0; i < x.size(); ++i) h[std::size_t(std::min(bins - 1, int((x[i] - lo) * scale)))] += w[i], total += w[i];
  const auto at = [&](double target) {
    double sum = 0;
    for (int b = 0; b < bins; ++b) {
      const double hb = h[std::size_t(b)];
      if (hb > 0 && sum + hb >= target) return lo + (b + (target - sum) / hb) / scale;
      sum += hb;
    }
    return hi;
  };
  return {at(q * total), at((1 - q) * total)};
}

inline bool finite3(const float* p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// A set of indices below n that empties in constant time: each index holds the generation that
/// last marked it, and clear() starts a new generation (the buffer is filled only when the counter
/// wraps). Per-thread instances let the many small searches of a frame skip frame-sized clears.
class Stamps {
 public:
  /// Empties the set and makes room for indices below n.
  void clear(std::size_t n) {
    if (stamp_.size() < n) stamp_.assign(n, 0), generation_ = 0;
    if (++generation_ == 0) std::fill(stamp_.begin(), stamp_.end(), 0), generation_ = 1;
  }
  /// Adds i; false when it was already in.
  bool insert(std::size_t i) {
    if (stamp_[i] == generation_) return false;
    stamp_[i] = generation_;
    return true;
  }
  bool contains(std::size_t i) const { return stamp_[i] == generation_; }

 private:
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
};

/// Everything the search reads, built once per call.
struct Pixels {
  const Cloud& cloud;
  const NormalMap& normals;
  const DetectOptions& o;
  int H, W;
  double focal;
  double cos_dev;
  std::vector<std::uint8_t> free;  // usable and not taken by a segment

  Pixels(const Cloud& c, const NormalMap& n, const DetectOptions& opt);
  /// The same frame and taken pixels under other options (a model-driven search).
  Pixels(const Pixels& parent, const DetectOptions& opt);

  Eigen::Vector3d p(int i) const {
    const float* q = cloud.data() + 3 * std::size_t(i);
    return Eigen::Vector3d(q[0], q[1], q[2]);
  }
  /// The unfiltered point of pixel i (DetectOptions::unfiltered) where it has one, else p(i).
  Eigen::Vector3d raw(int i) const {
    if (o.unfiltered.empty()) return p(i);
    const float* q = o.unfiltered.data() + 3 * std::size_t(i);
    return finite3(q) ? Eigen::Vector3d(q[0], q[1], q[2]) : p(i);
  }
  Eigen::Vector3d n(int i) const {
    return Eigen::Vector3d(normals.data()[3 * i], normals.data()[3 * i + 1], normals.data()[3 * i + 2]);
  }
  double eps(double z) const { return o.epsilon * std::max(0.3, 1 + o.epsilon_growth * (z * z - 1)); }
  /// +1 when pixel i's normal agrees with the outward normal of s at its closest point, -1 when it
  /// is opposed (a concave side: a mug's inner wall), 0 for shapes without an inside (planes).
  int orientation(const Segment& s, int i) const {
    if (!s.solid()) return 0;
    Eigen::Vector3d sn;
    s.signed_distance(p(i), &sn);
    return sn.dot(n(i)) >= 0 ? 1 : -1;
  }
  /// Pixel i fits segment s: distance within eps(z) and normal within the deviation, on the
  /// side `sign` (see orientation; 0 = either side). The sign keeps a mug's outer wall and its
  /// visible inner wall, a few millimetres apart but facing opposite ways, in different segments.
  bool fits(const Segment& s, int i, int sign = 0) const {
    return s.visit([&](const auto& g) { return fits_shape(g, i, sign); });
  }
  /// fits() for one shape (a loop over many pixels dispatches on the segment's class once).
  template <class Shape>
  bool fits_shape(const Shape& g, int i, int sign = 0) const {
    const Eigen::Vector3d x = p(i);
    Eigen::Vector3d sn;
    const double d = g.signed_distance(x, &sn);
    const double c = sn.dot(n(i));
    return std::abs(d) <= eps(x.z()) && (sign == 0 ? std::abs(c) : sign * c) >= cos_dev;
  }
  /// Pixel i is within eps(z) of s and its normal is not turned further than `min_cos` from the
  /// surface's outward normal: the test for thin parts whose normals are too noisy for fits(),
  /// and whose fitted tube may sit a little in front of or behind the points.
  bool near_facing(const Segment& s, int i, double min_cos) const {
    const Eigen::Vector3d x = p(i);
    Eigen::Vector3d sn;
    const double d = s.signed_distance(x, &sn);
    return std::abs(d) <= eps(x.z()) && sn.dot(n(i)) > min_cos;
  }
  /// The 4-connected component of free pixels that fit s, from `seed`, on a grid of `step`
  /// pixels (seed snapped to it); `mask` (optional) restricts it. Capped at `cap` cells.
  std::vector<int> component(const Segment& s, int seed, int step, const std::uint8_t* mask = nullptr,
                             std::size_t cap = SIZE_MAX) const;
  /// An image rectangle, inclusive.
  struct Box {
    int u0, v0, u1, v1;
  };
  /// The rectangle of the pixel indices `pix` (not empty).
  Box box_of(const std::vector<int>& pix) const {
    Box b{W, H, -1, -1};
    for (int i : pix)
      b.u0 = std::min(b.u0, i % W), b.u1 = std::max(b.u1, i % W), b.v0 = std::min(b.v0, i / W),
      b.v1 = std::max(b.v1, i / W);
    return b;
  }
  /// `b` grown by `by` pixels each way, clipped to the frame.
  Box grown(const Box& b, int by) const {
    return {std::max(0, b.u0 - by), std::max(0, b.v0 - by), std::min(W - 1, b.u1 + by), std::min(H - 1, b.v1 + by)};
  }
  /// The shape limits of the options.
  shapes::Limits limits(double min_radius, double max_radius) const {
    return {min_radius, max_radius, o.min_minor_radius, o.max_minor_radius, o.max_major_radius};
  }
};

/// A candidate of the search: its shape, seed pixel, estimated inlier pixels.
struct Candidate {
  Segment s;
  int seed = -1;
  double score = 0;
};

/// Sorts pixel indices below n (a frame's pixel count) ascending, as std::sort does.
void sort_pixels(std::vector<int>& pix, int n);
/// Sets a segment's pixels, inlier count, visible extent, canonical sign, inward flag and mean
/// colour and hue (when `color` is given).
void describe(const Pixels& f, Segment& s, std::vector<int> pix, const ColorImage* color);
/// How much an axial segment bends along its axis, as its pixels' normals show: Segment::bend
/// (the pixels next to a torus among `others`, a handle's roots, left out).
void measure_bend(const Pixels& f, Segment& s, const std::vector<Segment>& others = {});
/// How far an axial segment seen from outside is from round across its axis, as its pixels'
/// distances from the surface show: Segment::out_of_round (handle roots left out as above).
void measure_out_of_round(const Pixels& f, Segment& s, const std::vector<Segment>& others = {});
/// A segment's mean colour and hue over its pixels (nothing without a colour image).
void set_color(Segment& s, const ColorImage* color);

/// Upright cylinders (standing on `support`: its normal and offset, DetectOptions::support),
/// found without normals: circles in the support plane fitted to patches of points
/// (features/upright.cpp), in the free pixels of `f` and those of the segments `out` found so far.
/// At most `max_count` are appended to `out`, each with at least `min_support` pixels, a radius in
/// [min_r, max_r] and its foot on the support; one replaces the segments whose pixels it takes
/// most of when it holds clearly more pixels than they did, and an upright body its circle would
/// overlap when it holds twice that body's pixels (else it is no body). Their pixels are taken.
void search_upright(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, int min_support, double min_r,
                    double max_r, int max_count, const ColorImage* color);

/// Whether the foot of a body seen in `pix`, whose lowest points lie `foot` metres above `support`
/// (its normal and offset), is hidden by something standing in front of it: below the body's
/// lowest pixels in the image (the support's normal projected there; its direction needs no
/// principal point) lie points higher than they are (features/upright.cpp). Below a wall in the
/// image lie its lower part, the support in front of it, or what stands in front of it; a base the
/// body stands on (a box, a drill's battery under its grip) lies no higher than its foot.
bool foot_hidden(const Pixels& g, const Eigen::Vector4d& support, const std::vector<int>& pix, double foot);

/// The bodies of `out` found bottom-up whose axis leans a little from `support`'s normal, refitted
/// with the axis held to it (features/upright.cpp): a standing body's axis is the support's normal,
/// and one side of a cylinder in wavy stereo depth fits a cone with a leaning axis. A held cylinder
/// or cone (radius in [min_r, max_r]) replaces a segment when it fits its points about as well.
void hold_upright(const Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, double min_r, double max_r);

/// The outer walls of the open vessels of `out` of which only the inside was found (an upright
/// inward cylinder: the far wall seen through the rim), looked for about the inside's axis
/// (features/upright.cpp): wavy stereo depth beyond a metre can hide a mug's outer wall from the
/// searches that do not know where its axis is. An outer wall found is appended to `out` (its
/// radius a wall's thickness beyond the inside's, its pixels taken).
void outer_walls(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, double min_r, double max_r,
                 const ColorImage* color);

/// The upright bodies of `out` (outer walls) grown into the free pixels connected to them that fit
/// them with the normals held loosely, as search_upright's are (wavy stereo depth leaves a
/// bottom-up body a patch of its wall); a cylinder's circle is refitted to them, the axis held.
/// Their pixels are taken; returns the pixels each segment of `out` grew by.
std::vector<std::vector<int>> grow_upright(Pixels& f, const Eigen::Vector4d& support, std::vector<Segment>& out, double min_r, double max_r,
                  const ColorImage* color);

/// An upright tapered body that may carry a handle (an outer cone standing on `support`, tapering
/// by at most a mug's), as the cylinder of its widest radius: the handle search looks next
/// to it (features/upright.cpp). None for any other segment.
std::optional<Segment> upright_cone_as_cylinder(const Eigen::Vector4d& support, const Segment& s);

/// An upright cone found to carry a handle refitted as the upright cylinder of its pixels (the
/// axis held): wavy stereo depth and a handle's roots lean a mug's wall into a false taper
/// (features/upright.cpp). False, and s unchanged, when the circle's radius leaves [min_r, max_r]
/// or the pixels still fit a cone clearly better (upright_cone's test).
bool hold_as_cylinder(const Pixels& f, const Eigen::Vector4d& support, Segment& s, double min_r, double max_r,
                      const ColorImage* color);

/// A handle seen in the colour image beside `body`'s silhouette, where the depth has little of it
/// (a thin tube beyond a metre: stereo depth loses or fattens it): the pixels of a half-plane
/// through the axis, out to a handle's reach, that have the body's colour and not the background's,
/// and depth near that plane or none, connected to the silhouette, and shaped as a handle is
/// (reach, height span, a loop that does not fill its box); where 30% or more have depth, their
/// median stands off the wall. The half-planes are those of the two limbs, and those turned from them about the axis
/// by up to `max_turn_deg` (in 15 degree steps; a handle seen obliquely), which need some of the
/// pixels to have depth. Returns a torus in the plane of the largest such silhouette, attached to
/// the wall, with its pixels; nothing without a colour image.
std::optional<Segment> colour_handle(const Pixels& f, const Segment& body, const ColorImage* color,
                                     double max_turn_deg);

/// A handle seen as its outline in the colour image beside `body`'s silhouette, where neither the
/// depth nor the silhouette's colours (colour_handle) showed it: an edge chain of the zone about
/// the body (signal::detect_edges on that box) that leaves a limb and comes back to it within the
/// body's height, standing off it as a handle does (reach and height span), with the body's colour
/// on its inner side and not on its outer one, and, where the inner side has depth, that depth
/// near the axis (not an object's outline behind the body). Returns a torus in the limb's plane,
/// attached to the wall, with the inner side's pixels; nothing without a colour image.
std::optional<Segment> edge_handle(const Pixels& f, const Segment& body, const ColorImage* color);

/// The model-driven handle search next to cylinder `body` over the pixels `region` (free ones
/// count), with the options' HandleOptions (features/handle.hpp): at most `max_count` handles, each
/// with at least `min_support` pixels, plausible within `limits`; their pixels are taken.
std::vector<Segment> search_handles(Pixels& f, const Segment& body, const std::vector<int>& region, int min_support,
                                    int max_count, const ColorImage* color, const shapes::Limits& limits);

}  // namespace mereo::features::detail
