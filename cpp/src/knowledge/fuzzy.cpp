// Trapezoidal fuzzy memberships (the attribute ranges of object models).
#include "mereo/knowledge/fuzzy.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace mereo::knowledge {

Membership Membership::range(double lo, double hi, double margin) {
  return {lo - margin, lo, hi, hi + margin};
}
Membership Membership::at_most(double full, double zero) {
  const double inf = std::numeric_limits<double>::infinity();
  return {-inf, -inf, full, zero};
}
Membership Membership::at_least(double zero, double full) {
  const double inf = std::numeric_limits<double>::infinity();
  return {zero, full, inf, inf};
}
Membership Membership::any() {
  const double inf = std::numeric_limits<double>::infinity();
  return {-inf, -inf, inf, inf};
}

double Membership::operator()(double x) const {
  if (std::isnan(x)) return 0.0;
  if (x < a || x > d) return 0.0;
  if (x < b) return (x - a) / (b - a);  // b > a here (x >= a and x < b)
  if (x <= c) return 1.0;
  return (d - x) / (d - c);             // c < x <= d
}

bool Membership::within(const Membership& outer) const { return a >= outer.a && d <= outer.d; }

std::string Membership::str() const {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g, %g)", a, b, c, d);
  return buf;
}

}  // namespace mereo::knowledge
