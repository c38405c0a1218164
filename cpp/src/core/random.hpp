// The random draws of the RANSAC searches (features/primitives.cpp, features/upright.cpp): one
// small generator per task, seeded by (seed, round, task), so that a result depends on the seed
// only, not on the threads. SplitMix64 (Steele, Lea and Flood 2014): one state word, a few
// multiplications per draw. A task draws a few hundred numbers; std::mt19937_64 spent more on
// seeding and refilling its 312 words than the search spent on them (11% of bench_primitives'
// profile).
#pragma once

#include <cstdint>
#include <limits>

namespace mereo::detail {

class TaskRandom {
 public:
  using result_type = std::uint64_t;
  /// The stream of task `task` of round `round` under `seed`; neighbouring keys give unrelated
  /// streams (the key is mixed before it becomes the state).
  TaskRandom(std::uint64_t seed, std::uint64_t round, std::uint64_t task)
      : s_(mix(mix(seed * 0x9E3779B97F4A7C15ULL + round) + task)) {}

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }
  result_type operator()() { return mix(s_ += 0x9E3779B97F4A7C15ULL); }
  /// Uniform in [0, n) (Lemire's multiply-shift: no division; its bias, n / 2^64, is nil here).
  int below(std::uint64_t n) { return int((static_cast<unsigned __int128>((*this)()) * n) >> 64); }

 private:
  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::uint64_t s_;
};

}  // namespace mereo::detail
