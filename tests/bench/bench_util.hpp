// Small helpers shared by the benchmarks: a millisecond clock and the median.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
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

}  // namespace mereo::bench
