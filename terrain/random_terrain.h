// MakeRandomTerrain: seeded fractal ground that is bit-identical for one seed on every machine.
#pragma once

#include <cstdint>

#include "terrain/height_grid.h"

namespace dt {

struct RandomTerrainParams {
  int posts_x = 257;  // posts along x (east)
  int posts_z = 257;  // posts along z (north)
  double spacing_m = 10.0;
  double relief_m = 100.0;  // elevations lie in [0, relief_m]
  uint64_t seed = 1;
  Material soil = Material::kGrass;
};

// Number of value-noise octaves summed by MakeRandomTerrain.
inline constexpr int kRandomTerrainOctaves = 6;

// Value noise summed over kRandomTerrainOctaves octaves (docs/terrain.md, "Files and digest").
// Lattice values come from splitmix64 and everything up to the final scaling is integer
// arithmetic, so the posts are equal bit for bit on every machine for one seed. The noise is
// defined on a square of n = max(posts_x, posts_z) posts a side; a rectangular grid is that
// square's south-west posts_x x posts_z corner, so it is the same ground as the square one would
// be where they overlap.
// Throws std::invalid_argument for a bad shape (as HeightGrid) or a relief_m that is not finite
// or is negative.
HeightGrid MakeRandomTerrain(const RandomTerrainParams& params);

// The splitmix64 output function (Steele, Lea and Flood 2014) applied to one state value:
// the state is advanced by 0x9E3779B97F4A7C15 and mixed. Exposed for tests.
uint64_t SplitMix64(uint64_t state);

}  // namespace dt
