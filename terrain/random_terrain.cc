#include "terrain/random_terrain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace dt {
namespace {

constexpr int64_t kWeightOne = int64_t{1} << 16;  // smoothstep weights in 16-bit fixed point
constexpr int64_t kLatticeHalfRange = int64_t{1} << 20;

// Lattice value of octave `octave` at lattice point (a, b): 21 random bits centred on zero.
int64_t LatticeValue(uint64_t seed, int octave, uint64_t a, uint64_t b) {
  const uint64_t h = SplitMix64(SplitMix64(SplitMix64(SplitMix64(seed) + octave) + a) + b);
  return static_cast<int64_t>(h >> 43) - kLatticeHalfRange;
}

// Smoothstep 3t^2 - 2t^3 at t = r / cell, in 16-bit fixed point, rounded down. Integer only, so
// every machine gets the same weight; r^2 (3 cell - 2 r) <= cell^3 < 2^48, so the shift fits.
int64_t SmoothWeight(int64_t r, int64_t cell) {
  const uint64_t num = static_cast<uint64_t>(r * r * (3 * cell - 2 * r));
  const uint64_t den = static_cast<uint64_t>(cell * cell * cell);
  return static_cast<int64_t>((num << 16) / den);
}

}  // namespace

uint64_t SplitMix64(uint64_t state) {
  uint64_t z = state + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

HeightGrid MakeRandomTerrain(const RandomTerrainParams& params) {
  if (!std::isfinite(params.relief_m) || params.relief_m < 0.0) {
    throw std::invalid_argument(
        fmt::format("relief_m = {} must be finite and >= 0", params.relief_m));
  }
  const int nx = params.posts_x, nz = params.posts_z;
  for (const auto& [name, v] : {std::pair{"posts_x", nx}, std::pair{"posts_z", nz}}) {
    if (v < 2 || v > kMaxPostsPerSide) {
      throw std::invalid_argument(
          fmt::format("{} = {} must be in [2, {}]", name, v, kMaxPostsPerSide));
    }
  }
  // The noise is defined on an n x n square (its cells are fractions of n); a rectangle takes
  // the square's south-west corner.
  const int n = std::max(nx, nz);
  const size_t count = static_cast<size_t>(nx) * static_cast<size_t>(nz);
  // Octave o adds value noise with cells of cell[o] posts and weight 2^(K-1-o): the first octave
  // spans half the grid, each next one halves the cell and the amplitude.
  int64_t cell[kRandomTerrainOctaves];
  for (int o = 0; o < kRandomTerrainOctaves; ++o) {
    cell[o] = std::max<int64_t>(1, static_cast<int64_t>(n - 1) >> (o + 1));
  }
  // Lattice values per octave, computed once per lattice point (at most 129 x 129 per octave).
  std::vector<int64_t> lattice_side(kRandomTerrainOctaves);
  std::vector<std::vector<int64_t>> lattice(kRandomTerrainOctaves);
  for (int o = 0; o < kRandomTerrainOctaves; ++o) {
    const int64_t side = (n - 1) / cell[o] + 2;
    lattice_side[o] = side;
    lattice[o].resize(static_cast<size_t>(side * side));
    for (int64_t b = 0; b < side; ++b) {
      for (int64_t a = 0; a < side; ++a) {
        lattice[o][static_cast<size_t>(b * side + a)] =
            LatticeValue(params.seed, o, static_cast<uint64_t>(a), static_cast<uint64_t>(b));
      }
    }
  }
  // |total| < 2^52 * 63 < 2^58; total >> 6 is below 2^52, so its conversion to double is exact,
  // and the division below maps it to [-1, 1]. The remaining steps are single IEEE operations
  // (no multiply feeding an add, so no fused multiply-add can change the result).
  constexpr int64_t kWeightSum = (int64_t{1} << kRandomTerrainOctaves) - 1;
  const double denominator = static_cast<double>(kWeightSum * (int64_t{1} << 46));
  const double half_relief_m = 0.5 * params.relief_m;
  std::vector<float> posts(count);
  std::vector<int64_t> total(static_cast<size_t>(nx));  // one row at a time
  for (int64_t j = 0; j < nz; ++j) {
    std::fill(total.begin(), total.end(), 0);
    for (int o = 0; o < kRandomTerrainOctaves; ++o) {
      const int64_t c = cell[o];
      const int64_t octave_weight = int64_t{1} << (kRandomTerrainOctaves - 1 - o);
      const int64_t side = lattice_side[o];
      const int64_t* south_row = &lattice[o][static_cast<size_t>((j / c) * side)];
      const int64_t* north_row = south_row + side;
      const int64_t wz = SmoothWeight(j % c, c);
      for (int64_t i = 0; i < nx; ++i) {
        const int64_t a = i / c;
        const int64_t wx = SmoothWeight(i % c, c);
        // |L| <= 2^20 and the weights of each pair sum to 2^16, so |v| <= 2^52.
        const int64_t south = south_row[a] * (kWeightOne - wx) + south_row[a + 1] * wx;
        const int64_t north = north_row[a] * (kWeightOne - wx) + north_row[a + 1] * wx;
        const int64_t v = south * (kWeightOne - wz) + north * wz;
        total[static_cast<size_t>(i)] += v * octave_weight;
      }
    }
    for (int64_t i = 0; i < nx; ++i) {
      const double unit = static_cast<double>(total[static_cast<size_t>(i)] >> 6) / denominator;
      posts[static_cast<size_t>(j * nx + i)] = static_cast<float>((unit + 1.0) * half_relief_m);
    }
  }
  return HeightGrid(nx, nz, params.spacing_m, std::move(posts), params.soil);
}

}  // namespace dt
