// Unit tests of the contact surface: kept ground planes and gathered earthworks answer as the
// terrain.
#include "vehicle/contact_surface.h"

#include <random>

#include <gtest/gtest.h>

#include "terrain/random_terrain.h"

namespace dt::test {
namespace {

// True if (x, z) lies in a bitgrid cell that features cover (Terrain::SquareBits).
bool InFeatureCell(const Terrain& t, double x_m, double z_m) {
  const HeightGrid::Location at = t.ground().Locate(x_m, z_m);
  const int cx = std::min(static_cast<int>(at.u * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  const int cz = std::min(static_cast<int>(at.v * kBitgridCellsPerSide), kBitgridCellsPerSide - 1);
  return ((t.SquareBits(at.square) >> (cz * kBitgridCellsPerSide + cx)) & 1u) != 0;
}

// Contacts walked in short random steps over rolling ground (32 m posts, so a bitgrid cell is
// 8 m) with many craters and berms: wherever the kept plane answers, in bare cells and in the
// bare parts of cells that features cover, it gives the height, normal and soil of a fresh
// sample; and it does answer in cells that features cover.
TEST(ContactSurface, KeptGroundPlaneAnswersAsAFreshSample) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    RandomTerrainParams p;
    p.posts_x = p.posts_z = 33;
    p.spacing_m = 32.0;
    p.relief_m = 40.0;
    p.seed = seed;
    Terrain t(MakeRandomTerrain(p));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> pos(100, 924), unit(0, 1);
    uint32_t number = 1;
    for (int k = 0; k < 300; ++k) {
      (void)t.Add({1, 1, number++}, FeatureParams::Crater(pos(rng), pos(rng), 2 + 6 * unit(rng)));
    }
    for (int k = 0; k < 60; ++k) {
      (void)t.Add({1, 1, number++},
                  FeatureParams::Berm(pos(rng), pos(rng), 6.28 * unit(rng), 5 + 10 * unit(rng),
                                      3 + 3 * unit(rng), 0.5 + unit(rng)));
    }
    int compared = 0, kept_in_feature_cells = 0, over_earthworks = 0;
    for (int walk = 0; walk < 200; ++walk) {
      const double cx = pos(rng), cz = pos(rng);
      // The vehicle's gathered earthworks: every one whose bounds overlap its area.
      const Rect area = Rect{cx, cz, cx, cz}.Expanded(30.0);
      std::vector<NearEarthwork> near;
      EarthworksNear(t, area, near);
      const KnownEarthworks known{near, area};
      GroundPlaneCache cache;
      double x = cx, z = cz;
      const double heading = 6.28 * unit(rng);
      for (int step = 0; step < 150; ++step) {
        // Mostly straight, 0.05-0.45 m a step, as a contact moves; sometimes past the area.
        x += std::cos(heading) * (0.05 + 0.4 * unit(rng));
        z += std::sin(heading) * (0.05 + 0.4 * unit(rng));
        const bool was_valid = cache.valid;
        const SurfaceSample kept = SampleSurface(t, {}, known, x, z, 1e9, cache);
        const SurfaceSample fresh = SampleSurface(t, {}, x, z, 1e9);
        ASSERT_NEAR(kept.height_m, fresh.height_m, 1e-9) << seed << " " << x << " " << z;
        ASSERT_NEAR((kept.normal - fresh.normal).norm(), 0.0, 1e-9) << seed << " " << x << " " << z;
        ASSERT_EQ(kept.material, fresh.material) << seed << " " << x << " " << z;
        // Over an earthwork the gathered earthworks give the terrain's own surface, bit for bit
        // (a crater's bowl is a cut below the ground).
        double e = 0.0;
        if (area.Contains(x, z) && EarthworkElevationAt(t, near, x, z, e)) {
          ASSERT_EQ(e, t.ElevationAt(x, z)) << seed << " " << x << " " << z;
          ++over_earthworks;
        }
        ++compared;
        if (was_valid && cache.valid && InFeatureCell(t, x, z)) ++kept_in_feature_cells;
      }
    }
    std::printf(
        "seed %d: %d samples, %d answered by a plane kept in a cell that features cover, %d over "
        "earthworks\n",
        static_cast<int>(seed), compared, kept_in_feature_cells, over_earthworks);
    EXPECT_GT(kept_in_feature_cells, compared / 100) << seed;
    EXPECT_GT(over_earthworks, compared / 100) << seed;
  }
}

}  // namespace
}  // namespace dt::test
