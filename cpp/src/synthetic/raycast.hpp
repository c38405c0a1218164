// Private to the synthetic renderer: deterministic random numbers and analytic ray casting.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace mereo::synthetic {
struct Shape;
}

namespace mereo::synthetic::detail {

using Vec3 = Eigen::Vector3d;

// ---- deterministic random numbers (identical on every platform) ---------------------------

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// A uniform double in [0, 1) from 64 random bits.
inline double unit_from_bits(std::uint64_t bits) {
  return double(bits >> 11) * (1.0 / 9007199254740992.0);
}

/// Counter-based hash of a tuple: the per-pixel noise source (no shared state).
inline std::uint64_t hash4(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
  std::uint64_t h = splitmix64(a ^ 0x6A09E667F3BCC909ull);
  h = splitmix64(h ^ b);
  h = splitmix64(h ^ (c * 0x9E3779B97F4A7C15ull));
  h = splitmix64(h ^ d);
  return h;
}

/// Sequential generator for scene construction (splitmix64 stream).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(splitmix64(seed ^ 0xD1B54A32D192ED03ull)) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return unit_from_bits(next()); }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// Integer in [lo, hi] (inclusive).
  int integer(int lo, int hi) {
    const std::uint64_t n = std::uint64_t(hi - lo + 1);
    return lo + int(next() % n);
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// ---- primitives in a common frame (the camera frame while rendering) ----------------------

enum class Kind { Plane, Box, Cylinder, Disc, SphereZone, Torus, Cone, Ellipsoid, Ring };

struct Prim {
  Kind kind = Kind::Plane;
  Vec3 c = Vec3::Zero();          // centre / point
  Vec3 a = Vec3::UnitZ();         // axis / normal
  Vec3 b = Vec3::UnitX();         // reference axis (box local x, torus arc zero)
  Vec3 e = Vec3::UnitY();         // a x b (box local y, torus arc +90 deg)
  Vec3 half = Vec3::Zero();       // box and ellipsoid half extents (x, y, z) = (b, e, a)
  double r = 0;                   // radius / outer radius / torus major radius
  double r_in = 0;                // disc and ring inner radius / torus minor radius
  double half_h = 0;              // cylinder, cone and ring half height
  double slope = 0;               // cone: tan(half-angle), its radius r + slope * (along a)
  double hmin = 0, hmax = 0;      // sphere zone offsets along a
  double arc0 = 0, arc_len = 0;   // torus and ring arc [arc0, arc0 + arc_len] from b towards e;
                                  // arc_len >= 2 pi: all
  bool clip = false;              // do not render inside this solid cylinder (a mug's handle)
  Vec3 clip_c = Vec3::Zero(), clip_a = Vec3::UnitZ();
  double clip_r = 0, clip_half_h = 0;
  std::uint32_t label = 0;        // part label
  std::uint32_t object = 0;       // object id
};

struct Hit {
  double t = 0;
  Vec3 n = Vec3::Zero();  // unit, not yet oriented
};

constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kTorusStep = 0.0005;  // metres between samples of the torus quartic

// Kinds: Plane (c, normal a); Box (centre c, axes b e a, half); Cylinder (open: lateral surface,
// centre c, axis a, r, half_h); Cone (c, a, r at c, slope, half_h); Disc (c, normal a, r, r_in);
// SphereZone (c, r, offsets hmin..hmax along a); Torus (c, axis a, major r, minor r_in, arc);
// Ellipsoid (c, axes b e a, semi-axes half); Ring: an annular sector of a cylinder (the solid
// between radii r_in and r about the axis a through c, |offset| <= half_h, over the arc), its
// two lateral surfaces and two flat caps; open at the arc's ends (where a neighbour joins).

/// The nearest intersection of the ray o + t d (|d| = 1) with `p` for t in (tmin, tmax),
/// outside p's clip cylinder if it has one.
bool intersect(const Prim& p, const Vec3& o, const Vec3& d, double tmin, double tmax, Hit& hit);

/// A bounding sphere; radius < 0 means unbounded (planes).
struct Bound {
  Vec3 c = Vec3::Zero();
  double r = -1;
};

/// Does the ray hit the sphere with an entry before tmax and an exit after tmin?
inline bool ray_hits_sphere(const Bound& s, const Vec3& o, const Vec3& d, double tmin,
                            double tmax) {
  if (s.r < 0) return true;
  const Vec3 w = o - s.c;
  const double B = w.dot(d);
  const double C = w.squaredNorm() - s.r * s.r;
  const double disc = B * B - C;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  return (-B - sq) < tmax && (-B + sq) > tmin;
}

Bound bound_of(const Prim& p);

/// Appends the primitives of `s` (one, or the pieces of a composite: prims.cpp); throws
/// std::invalid_argument for an unknown class.
void append_prims(const Shape& s, std::vector<Prim>& out);

// ---- a scene of primitives, grouped by object ---------------------------------------------

struct RenderObject {
  Bound bound;
  int first = 0, count = 0;
  std::uint32_t id = 0;
  Eigen::Vector3f color;
};

struct RenderScene {
  std::vector<Prim> prims;
  std::vector<RenderObject> objects;
};

struct RayHit {
  double t = std::numeric_limits<double>::infinity();
  Vec3 n = Vec3::Zero();
  std::uint32_t label = 0, object = 0;
  int obj_index = -1;
};

/// Nearest hit along o + t d, t in (tmin, tmax).
bool cast_nearest(const RenderScene& rs, const Vec3& o, const Vec3& d, double tmin, double tmax,
                  RayHit& out);

/// Does anything block o + t d for t in (tmin, tmax)?
/// The ids (Prim::object) of the objects the ray meets anywhere along it, each once, in `out`;
/// the labels (Prim::label) of their parts it meets, each once, in `parts`.
void objects_hit(const RenderScene& rs, const Vec3& o, const Vec3& d, std::vector<std::uint32_t>& out,
                 std::vector<std::uint32_t>& parts);
bool cast_any(const RenderScene& rs, const Vec3& o, const Vec3& d, double tmin, double tmax);

}  // namespace mereo::synthetic::detail
