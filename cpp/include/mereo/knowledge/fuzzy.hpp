// mereo/knowledge/fuzzy.hpp: fuzzy membership functions (the attribute ranges of object models).
#pragma once

#include <string>

namespace mereo::knowledge {

/// A trapezoidal membership function: 0 at x <= a, rising linearly to 1 at b, 1 up to c,
/// falling linearly to 0 at d (a <= b <= c <= d). a == b (or c == d) gives a crisp edge.
/// An allowed range [lo, hi] with a soft margin m is the trapezoid (lo - m, lo, hi, hi + m),
/// the fuzzy "attribute within range" of Kasprzak et al. (eq. 5.5's membership factors).
struct Membership {
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;

  /// [lo, hi] with soft margins `margin` on both sides.
  static Membership range(double lo, double hi, double margin = 0.0);
  /// 1 for x <= full, falling to 0 at x >= zero (e.g. "distance at most").
  static Membership at_most(double full, double zero);
  /// 0 for x <= zero, rising to 1 at x >= full.
  static Membership at_least(double zero, double full);
  /// Everything (1 everywhere).
  static Membership any();

  /// The membership of x, in [0, 1]; NaN gives 0.
  double operator()(double x) const;
  /// True if [a, d] of this lies within [a, d] of `outer` (the support is narrower or equal).
  bool within(const Membership& outer) const;
  /// "(a, b, c, d)" for messages.
  std::string str() const;
};

}  // namespace mereo::knowledge
