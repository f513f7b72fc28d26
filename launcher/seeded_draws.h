// Seeded draws for drills: uniform reals and shuffles from mt19937_64 that are the same on every
// standard library (std::uniform_real_distribution and std::shuffle are not specified exactly).
#pragma once

#include <cstddef>
#include <random>
#include <utility>
#include <vector>

namespace dt {

// Uniform in [lo, hi) from the top 53 bits of one draw.
inline double SeededUniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

// Fisher-Yates (the modulo's slight bias does not matter for drills).
template <typename T>
void SeededShuffle(std::mt19937_64& rng, std::vector<T>& v) {
  for (size_t i = v.size(); i > 1; --i) {
    std::swap(v[i - 1], v[static_cast<size_t>(rng() % i)]);
  }
}

}  // namespace dt
