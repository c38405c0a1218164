// Small helpers shared by the benchmarks: a millisecond clock, the median, JSON numbers.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mereo::bench {

inline double now_ms() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

/// The median of v (NaN when empty).
inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The q-quantile of v, q in [0, 1] (NaN when empty); median(v) is quantile(v, 0.5) for odd sizes.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  const auto k = v.begin() + std::ptrdiff_t(std::min(v.size() - 1, std::size_t(q * double(v.size()))));
  std::nth_element(v.begin(), k, v.end());
  return *k;
}

/// x as a JSON number with `decimals` decimals; null when it is not finite (no figure).
inline std::string json_number(double x, int decimals = 3) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  return buf;
}

}  // namespace mereo::bench
