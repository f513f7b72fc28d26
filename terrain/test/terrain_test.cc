#include "terrain/terrain.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "terrain/berm.h"
#include "terrain/berm_operations.h"
#include "terrain/crater.h"
#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;

FeatureId Id(uint32_t n) { return {1, 1, n}; }

using test::SlopedGround;

double Above(const Terrain& t, double x, double z) {
  return t.ElevationAt(x, z) - t.GroundElevationAt(x, z);
}

void ExpectAdded(Terrain& t, FeatureId id, const FeatureParams& p) {
  auto s = t.Add(id, p);
  ASSERT_TRUE(s.ok()) << s.error().message;
}

// Elevations over a grid of points, for before/after comparisons.
std::vector<double> Sample(const Terrain& t, double x0, double z0, double x1, double z1,
                           double step) {
  std::vector<double> out;
  for (double x = x0; x <= x1; x += step) {
    for (double z = z0; z <= z1; z += step) out.push_back(t.ElevationAt(x, z));
  }
  return out;
}

TEST(TerrainBerm, CrestIsAtHeightAboveSlopedGroundAndEdgesAtGround) {
  Terrain t(SlopedGround());
  // One berm up the x slope, one across it, one diagonal.
  const std::array<double, 3> dirs = {0.0, kPi / 2, 2.3};
  for (size_t k = 0; k < dirs.size(); ++k) {
    ExpectAdded(t, Id(static_cast<uint32_t>(k + 1)),
                FeatureParams::Berm(100, 100, dirs[k], 60, 6, 2.5));
    const double c = std::cos(dirs[k]), s = std::sin(dirs[k]);
    for (double along = 0; along <= 60; along += 0.7) {
      const double x = 100 + along * c, z = 100 + along * s;
      EXPECT_NEAR(Above(t, x, z), 2.5, 1e-9) << along;
      // The outer edges are at the ground, the middle of each side slope halfway up.
      {
        EXPECT_NEAR(Above(t, x - 3 * s, z + 3 * c), 0.0, 1e-9) << along;
        EXPECT_NEAR(Above(t, x + 3 * s, z - 3 * c), 0.0, 1e-9) << along;
        EXPECT_NEAR(Above(t, x + 2 * s, z - 2 * c), 1.25, 1e-9) << along;
      }
    }
    ASSERT_TRUE(t.Remove(Id(static_cast<uint32_t>(k + 1))).ok());
  }
}

TEST(TerrainCrater, RimStandsAboveSlopedGroundAndCentreAndOutsideAreGround) {
  Terrain t(SlopedGround());
  const double cx = 101.3, cz = 99.1, r = 12;
  ExpectAdded(t, Id(1), FeatureParams::Crater(cx, cz, r));
  EXPECT_EQ(t.ElevationAt(cx, cz), t.GroundElevationAt(cx, cz));
  for (int k = 0; k < 64; ++k) {
    const double a = k * 2 * kPi / 64, c = std::cos(a), s = std::sin(a);
    for (double q : {0.6, 0.7, 0.8}) {  // the rim: rings 1 and 2 and between them
      EXPECT_NEAR(Above(t, cx + q * r * c, cz + q * r * s), 0.15 * r, 1e-9) << k << " " << q;
    }
    EXPECT_EQ(t.ElevationAt(cx + 0.3 * r * c, cz + 0.3 * r * s),
              t.GroundElevationAt(cx + 0.3 * r * c, cz + 0.3 * r * s));  // the floor
    EXPECT_EQ(t.ElevationAt(cx + 1.01 * r * c, cz + 1.01 * r * s),
              t.GroundElevationAt(cx + 1.01 * r * c, cz + 1.01 * r * s));  // outside
  }
}

TEST(TerrainBerm, OverlappingBermsGiveTheHigherSurface) {
  Terrain t(SlopedGround());
  ExpectAdded(t, Id(1), FeatureParams::Berm(60, 100, 0, 80, 10, 2));
  ExpectAdded(t, Id(2), FeatureParams::Berm(100, 60, kPi / 2, 80, 8, 3));
  const Feature* a = t.Find(Id(1));
  const Feature* b = t.Find(Id(2));
  // At the crossing the taller berm wins.
  EXPECT_NEAR(Above(t, 100, 100), 3.0, 1e-9);
  int both = 0, a_wins = 0;
  for (double x = 80; x <= 120; x += 0.25) {
    for (double z = 80; z <= 120; z += 0.25) {
      const double oa = a->OffsetAboveGround(x, z).value_or(0.0);
      const double ob = b->OffsetAboveGround(x, z).value_or(0.0);
      EXPECT_NEAR(Above(t, x, z), std::max(oa, ob), 1e-9) << x << "," << z;
      if (oa > 0 && ob > 0) {
        ++both;
        if (oa > ob) ++a_wins;
      }
    }
  }
  // Both berms overlap somewhere, and the lower one is sometimes the higher surface there.
  EXPECT_GT(both, 100);
  EXPECT_GT(a_wins, 10);
}

// A mixed set of overlapping features.
std::vector<FeatureParams> MixedFeatures() {
  std::vector<FeatureParams> out = {
      FeatureParams::Crater(90, 90, 12),
      WithCraterVertexEdit(FeatureParams::Crater(100, 95, 9), {3, 2, 4.0}),
      FeatureParams::Crater(105, 85, 6, Material::kRock),
      FeatureParams::Berm(70, 92, 0.1, 50, 7, 2.2),
      FeatureParams::Berm(95, 70, 1.4, 40, 5, 1.7, Material::kConcrete),
  };
  return out;
}

TEST(TerrainOrder, ElevationAndSoilDoNotDependOnInsertionOrder) {
  const auto features = MixedFeatures();
  Terrain forward(SlopedGround()), backward(SlopedGround());
  for (size_t k = 0; k < features.size(); ++k) {
    ExpectAdded(forward, Id(static_cast<uint32_t>(k + 1)), features[k]);
  }
  for (size_t k = features.size(); k-- > 0;) {
    ExpectAdded(backward, Id(static_cast<uint32_t>(k + 1)), features[k]);
  }
  int raised = 0;
  for (double x = 60; x <= 130; x += 0.173) {
    for (double z = 60; z <= 130; z += 0.173) {
      const double e = forward.ElevationAt(x, z);
      ASSERT_EQ(e, backward.ElevationAt(x, z)) << x << "," << z;  // exact
      ASSERT_EQ(forward.SoilAt(x, z), backward.SoilAt(x, z)) << x << "," << z;
      if (e > forward.GroundElevationAt(x, z)) ++raised;
    }
  }
  EXPECT_GT(raised, 1000);
}

TEST(TerrainBerm, BreachLeavesTwoBermsAndAGapAtGroundLevel) {
  Terrain t(SlopedGround());
  const FeatureParams p = FeatureParams::Berm(40, 50, 0.6, 100, 6, 2);
  ExpectAdded(t, Id(1), p);
  const auto pieces = BreachBerm(static_cast<const Berm&>(*t.Find(Id(1))), 50, 10);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  ASSERT_EQ(pieces.value().size(), 2u);
  ASSERT_TRUE(t.Remove(Id(1)).ok());
  ExpectAdded(t, Id(2), pieces.value()[0]);
  ExpectAdded(t, Id(3), pieces.value()[1]);
  EXPECT_EQ(t.feature_count(), 2u);
  const double c = std::cos(0.6), s = std::sin(0.6);
  for (double along = 0; along <= 100; along += 0.25) {
    const double x = 40 + along * c, z = 50 + along * s;
    if (along > 45 && along < 55) {
      EXPECT_EQ(t.ElevationAt(x, z), t.GroundElevationAt(x, z)) << along;
    } else if (along <= 43 || along >= 57) {
      EXPECT_NEAR(Above(t, x, z), 2.0, 1e-9) << along;
    }
  }
}

TEST(TerrainBerm, EmplacementCrestHasNoDipAtTheJoints) {
  Terrain t(SlopedGround());
  const double facing = 0.4;
  auto berms = EmplacementBerms({100, 100, facing, 30, 5, 1.8, Material::kDirt});
  ASSERT_TRUE(berms.ok());
  for (size_t k = 0; k < 3; ++k) ExpectAdded(t, Id(static_cast<uint32_t>(k + 1)), berms.value()[k]);
  const double fx = std::cos(facing), fz = std::sin(facing), lx = -fz, lz = fx;
  auto at = [&](double fwd, double left) {
    return std::pair(100 + fwd * fx + left * lx, 100 + fwd * fz + left * lz);
  };
  // Back-right -> front-right -> front-left -> back-left.
  const double corners[4][2] = {{-15, -15}, {15, -15}, {15, 15}, {-15, 15}};
  for (int leg = 0; leg < 3; ++leg) {
    for (int step = 0; step <= 200; ++step) {
      const double u = step / 200.0;
      const auto [x, z] = at(corners[leg][0] + u * (corners[leg + 1][0] - corners[leg][0]),
                             corners[leg][1] + u * (corners[leg + 1][1] - corners[leg][1]));
      EXPECT_NEAR(Above(t, x, z), 1.8, 1e-9) << "leg " << leg << " step " << step;
    }
  }
  const auto [cx, cz] = at(0, 0);
  EXPECT_EQ(t.ElevationAt(cx, cz), t.GroundElevationAt(cx, cz));
}

TEST(TerrainFeatures, AddUpdateRemoveRemoveAtRemoveAll) {
  Terrain t(SlopedGround());
  ExpectAdded(t, Id(1), FeatureParams::Crater(50, 50, 10));
  ExpectAdded(t, Id(2), FeatureParams::Crater(56, 50, 4));
  ExpectAdded(t, Id(3), FeatureParams::Berm(120, 120, 0, 30, 6, 2));
  EXPECT_EQ(t.feature_count(), 3u);
  ASSERT_NE(t.Find(Id(2)), nullptr);
  EXPECT_EQ(t.Find(Id(2))->params(), FeatureParams::Crater(56, 50, 4));
  EXPECT_NEAR(Above(t, 57, 50), 1.5, 1e-9);  // crater 1's rim (r = 7 of 10)
  EXPECT_NEAR(Above(t, 135, 120), 2.0, 1e-9);

  // Update: the berm grows taller and longer; the old shape is gone.
  ASSERT_TRUE(t.Update(Id(3), FeatureParams::Berm(120, 120, 0, 50, 6, 3)).ok());
  EXPECT_EQ(t.feature_count(), 3u);
  EXPECT_NEAR(Above(t, 135, 120), 3.0, 1e-9);
  EXPECT_NEAR(Above(t, 165, 120), 3.0, 1e-9);
  EXPECT_EQ(t.Find(Id(3))->params(), FeatureParams::Berm(120, 120, 0, 50, 6, 3));

  // RemoveAt removes only features covering the point, not others in the same square: crater 2
  // touches the square of (52.5, 53.5) but its rim is 4.95 m away.
  EXPECT_EQ(t.FeaturesNear(52.5, 53.5).size(), 2u);
  EXPECT_EQ(t.RemoveAt(52.5, 53.5), (std::vector<FeatureId>{Id(1)}));
  EXPECT_EQ(t.feature_count(), 2u);
  EXPECT_EQ(t.Find(Id(1)), nullptr);
  EXPECT_EQ(Above(t, 57, 50), 0.0);  // crater 2's floor
  ExpectAdded(t, Id(1), FeatureParams::Crater(50, 50, 10));
  EXPECT_EQ(t.RemoveAt(57.5, 50), (std::vector<FeatureId>{Id(1), Id(2)}));
  EXPECT_EQ(t.feature_count(), 1u);
  EXPECT_EQ(Above(t, 57, 50), 0.0);
  EXPECT_TRUE(t.RemoveAt(10, 10).empty());

  ASSERT_TRUE(t.Remove(Id(3)).ok());
  EXPECT_FALSE(t.Remove(Id(3)).ok());
  EXPECT_EQ(t.feature_count(), 0u);
  EXPECT_EQ(Above(t, 135, 120), 0.0);

  ExpectAdded(t, Id(4), FeatureParams::Crater(20, 20, 5));
  ExpectAdded(t, Id(5), FeatureParams::Berm(100, 20, 1, 20, 4, 1));
  t.RemoveAll();
  EXPECT_EQ(t.feature_count(), 0u);
  EXPECT_TRUE(t.FeaturesNear(20, 20).empty());
  EXPECT_FALSE(t.FeatureBitAt(20, 23));
  EXPECT_EQ(Above(t, 20, 23), 0.0);
  // IDs may be reused after removal.
  ExpectAdded(t, Id(4), FeatureParams::Crater(20, 20, 5));
}

TEST(TerrainFeatures, RefusedAddOrUpdateChangesNothing) {
  Terrain t(SlopedGround());
  ExpectAdded(t, Id(1), FeatureParams::Crater(50, 50, 10));
  ExpectAdded(t, Id(2), FeatureParams::Berm(40, 60, 0, 30, 6, 2));
  const auto before = Sample(t, 30, 30, 80, 80, 0.37);
  auto refused = [&](const Status& s, const std::string& needle) {
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find(needle), std::string::npos) << s.error().message;
    EXPECT_EQ(t.feature_count(), 2u);
    EXPECT_EQ(Sample(t, 30, 30, 80, 80, 0.37), before);
    EXPECT_EQ(t.Find(Id(1))->params(), FeatureParams::Crater(50, 50, 10));
    EXPECT_EQ(t.Find(Id(2))->params(), FeatureParams::Berm(40, 60, 0, 30, 6, 2));
  };
  refused(t.Add(Id(1), FeatureParams::Crater(60, 60, 3)), "already exists");
  refused(t.Add(Id(1), FeatureParams::Crater(60, 60, -3)), "already exists");  // named first
  refused(t.Add(Id(3), FeatureParams::Crater(60, 60, -3)), "-3");
  refused(t.Add(Id(3), FeatureParams::Crater(195, 60, 8)), "leaves the terrain");
  refused(t.Add({1, 1, 0}, FeatureParams::Crater(60, 60, 3)), "number 0");
  FeatureParams odd = FeatureParams::Crater(60, 60, 3);
  odd.length_m[2] = 1;
  refused(t.Add(Id(3), odd), "length_m[2]");
  refused(t.Update(Id(1), FeatureParams::Berm(50, 50, 0, 10, 3, 1)), "cannot make it a berm");
  refused(t.Update(Id(1), FeatureParams::Crater(50, 50, 300)), "300");
  refused(t.Update(Id(1), FeatureParams::Crater(5, 50, 10)), "leaves the terrain");
  refused(t.Update(Id(2), FeatureParams::Berm(40, 60, kPi, 45, 6, 2)), "leaves the terrain");
  refused(t.Update(Id(9), FeatureParams::Crater(50, 50, 10)), "does not exist");
  FeatureParams bad_edit = FeatureParams::Crater(50, 50, 10);
  bad_edit.vertex_edits = {{2, 1, 1.0}, {1, 1, 1.0}};
  refused(t.Update(Id(1), bad_edit), "sorted");
}

TEST(TerrainFeatures, OffTerrainPlacementIsRefusedWithTheExtent) {
  Terrain t(SlopedGround());
  auto s = t.Add(Id(1), FeatureParams::Crater(3, 100, 5));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("x [-2, 8]"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("[0, 200]"), std::string::npos) << s.error().message;
  s = t.Add(Id(1), FeatureParams::Berm(150, 100, 0, 60, 6, 2));  // runs past x = 200
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("leaves the terrain"), std::string::npos) << s.error().message;
  s = t.Add(Id(1), FeatureParams::Crater(250, 100, 5));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("250"), std::string::npos) << s.error().message;
  EXPECT_EQ(t.feature_count(), 0u);
  // Exactly touching the edge is on the terrain.
  ExpectAdded(t, Id(2), FeatureParams::Crater(5, 100, 5));
}

TEST(TerrainFeatures, FeatureCrossingSquaresIsListedInEachAndSetsBitsOnlyWhereItIs) {
  Terrain t(SlopedGround());  // 2 m squares, 0.5 m bitgrid cells
  const double cx = 51.3, cz = 47.9, r = 5.2;
  ExpectAdded(t, Id(1), FeatureParams::Crater(cx, cz, r));
  const Feature* f = t.Find(Id(1));
  const int mx = t.ground().squares_x(), mz = t.ground().squares_z();
  int listed = 0, bits_set = 0;
  for (int j = 0; j < mz; ++j) {
    for (int i = 0; i < mx; ++i) {
      const auto list = t.FeaturesInSquare({i, j});
      const double x0 = i * 2.0, z0 = j * 2.0;
      const bool touches_box = x0 <= cx + r && x0 + 2 >= cx - r && z0 <= cz + r && z0 + 2 >= cz - r;
      EXPECT_EQ(list.size(), touches_box ? 1u : 0u) << i << "," << j;
      if (!touches_box) {
        EXPECT_EQ(t.SquareBits({i, j}), 0) << i << "," << j;
        continue;
      }
      ++listed;
      EXPECT_EQ(list[0], f);
      for (int cz_i = 0; cz_i < kBitgridCellsPerSide; ++cz_i) {
        for (int cx_i = 0; cx_i < kBitgridCellsPerSide; ++cx_i) {
          // Nearest point of the cell to the centre decides whether the disc reaches it.
          const double ax = x0 + cx_i * 0.5, az = z0 + cz_i * 0.5;
          const double nx = std::clamp(cx, ax, ax + 0.5), nz = std::clamp(cz, az, az + 0.5);
          const double d = std::hypot(nx - cx, nz - cz);
          const bool bit = (t.SquareBits({i, j}) >> (cz_i * 4 + cx_i)) & 1u;
          if (d < r - 1e-6) {
            EXPECT_TRUE(bit) << i << "," << j << " cell " << cx_i << "," << cz_i;
          } else if (d > r + 1e-6) {
            EXPECT_FALSE(bit) << i << "," << j << " cell " << cx_i << "," << cz_i;
          }
          bits_set += bit;
          // FeatureBitAt agrees at the cell's centre.
          EXPECT_EQ(t.FeatureBitAt(ax + 0.25, az + 0.25), bit);
        }
      }
    }
  }
  // The box spans 6 x 6 squares; the disc's bits are about pi r^2 / 0.25 plus the rim cells.
  EXPECT_EQ(listed, 36);
  EXPECT_GT(bits_set, 340);
  EXPECT_LT(bits_set, 36 * 16);
}

TEST(TerrainFeatures, DiagonalBermSetsBitsAlongItsFootprintOnly) {
  Terrain t(SlopedGround());  // 2 m squares, 0.5 m cells
  const double x0 = 60.3, z0 = 40.7, dir = 0.8, length = 30, width = 3;
  ExpectAdded(t, Id(1), FeatureParams::Berm(x0, z0, dir, length, width, 1));
  const double c = std::cos(dir), s = std::sin(dir), run = width / 3;
  const Feature* f = t.Find(Id(1));
  const SquareIndex lo = t.ground().SquareAt(f->Bounds().min_x, f->Bounds().min_z);
  const SquareIndex hi = t.ground().SquareAt(f->Bounds().max_x, f->Bounds().max_z);
  int cells = 0, bits_set = 0;
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      ASSERT_EQ(t.FeaturesInSquare({i, j}).size(), 1u) << i << "," << j;
      for (int cell = 0; cell < 16; ++cell) {
        const double ax = i * 2.0 + (cell % 4) * 0.5, az = j * 2.0 + (cell / 4) * 0.5;
        const bool bit = (t.SquareBits({i, j}) >> cell) & 1u;
        ++cells;
        bits_set += bit;
        // Any covered sample point in the cell needs the bit.
        bool covered = false;
        for (int k = 0; k <= 10; ++k) {
          for (int m = 0; m <= 10; ++m) covered |= f->Covers(ax + k * 0.05, az + m * 0.05);
        }
        if (covered) {
          EXPECT_TRUE(bit) << i << "," << j << " cell " << cell;
        }
        // A set bit needs the footprint within half a cell diagonal of the cell's centre.
        const double dx = ax + 0.25 - x0, dz = az + 0.25 - z0;
        const double along = dx * c + dz * s, left = dz * c - dx * s;
        const bool near = std::abs(left) <= width / 2 + 0.36 && along >= -run - 0.36 &&
                          along <= length + run + 0.36;
        if (bit) {
          EXPECT_TRUE(near) << i << "," << j << " cell " << cell;
        }
      }
    }
  }
  // The box of a diagonal strip is mostly empty.
  EXPECT_GT(bits_set, 0);
  EXPECT_LT(bits_set, cells / 3);
}

// Adding ORs a feature's cells in, removing recomputes the square: after any sequence both must
// give what a terrain built afresh from the survivors gives.
TEST(TerrainFeatures, BitsAfterAddsAndRemovesEqualBitsOfAFreshTerrain) {
  Terrain t(SlopedGround());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(20.0, 180.0), radius(0.3, 6.0), unit(0.0, 1.0);
  std::vector<uint32_t> live;
  uint32_t next = 1;
  for (int step = 0; step < 400; ++step) {
    if (live.empty() || unit(rng) < 0.6) {
      // Crater edges on cell edges (multiples of 0.5 m) test the closed-cell rule.
      const double x = unit(rng) < 0.3 ? std::round(pos(rng)) + 0.5 : pos(rng);
      const double r = unit(rng) < 0.3 ? std::round(radius(rng)) + 0.5 : radius(rng);
      const FeatureParams p =
          unit(rng) < 0.8 ? FeatureParams::Crater(x, pos(rng), r)
                          : FeatureParams::Berm(x, pos(rng), 6.0 * unit(rng), 10.0 * r, 3.0, 1.0);
      if (t.Add(Id(next), p).ok()) live.push_back(next++);  // a long berm may leave the terrain
    } else {
      const size_t k = static_cast<size_t>(unit(rng) * static_cast<double>(live.size()));
      ASSERT_TRUE(t.Remove(Id(live[k])).ok());
      live.erase(live.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  Terrain fresh(SlopedGround());
  for (const Feature* f : t.FeaturesById()) ExpectAdded(fresh, f->id(), f->params());
  const int mx = t.ground().squares_x(), mz = t.ground().squares_z();
  int differing = 0, nonzero = 0;
  for (int j = 0; j < mz; ++j) {
    for (int i = 0; i < mx; ++i) {
      differing += t.SquareBits({i, j}) != fresh.SquareBits({i, j});
      nonzero += t.SquareBits({i, j}) != 0;
    }
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(nonzero, 500);  // the check compared real masks, not empty squares
}

TEST(TerrainFeatures, FindAgreesWithTheAddedAndRemovedIdsOfManyOrigins) {
  // Enough adds and removes of interleaved origins, with some numbers far apart, that the ID
  // table grows several times and removals shift probe runs.
  Terrain t(SlopedGround());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(20.0, 180.0), unit(0.0, 1.0);
  std::set<FeatureId> live;
  std::map<NodeAddress, uint32_t> next;
  for (int step = 0; step < 6000; ++step) {
    if (live.empty() || unit(rng) < 0.65) {
      const NodeAddress origin{1, static_cast<uint16_t>(1 + static_cast<int>(unit(rng) * 4))};
      uint32_t& n = next[origin];
      n += unit(rng) < 0.05 ? 100000 : 1;
      const FeatureId id{origin.site, origin.host, n};
      ASSERT_TRUE(t.Add(id, FeatureParams::Crater(pos(rng), pos(rng), 1.0)).ok());
      live.insert(id);
      EXPECT_FALSE(t.Add(id, FeatureParams::Crater(100, 100, 1.0)).ok());  // already held
    } else {
      auto it = live.begin();
      std::advance(it, static_cast<std::ptrdiff_t>(unit(rng) * static_cast<double>(live.size())));
      ASSERT_TRUE(t.Remove(*it).ok());
      EXPECT_EQ(t.Find(*it), nullptr);
      EXPECT_FALSE(t.Remove(*it).ok());
      live.erase(it);
    }
  }
  ASSERT_EQ(t.feature_count(), live.size());
  ASSERT_GT(live.size(), 1000u);
  for (const FeatureId& id : live) {
    const Feature* f = t.Find(id);
    ASSERT_NE(f, nullptr) << id.ToString();
    EXPECT_EQ(f->id(), id);
  }
  const auto by_id = t.FeaturesById();
  ASSERT_EQ(by_id.size(), live.size());
  auto expected = live.begin();
  for (const Feature* f : by_id) EXPECT_EQ(f->id(), *expected++);
  EXPECT_EQ(t.Find({1, 9, 1}), nullptr);
}

TEST(TerrainFeatures, SetPostElevationMovesACraterWithTheGround) {
  Terrain t(HeightGrid(51, 2.0, 10.0f));
  ExpectAdded(t, Id(1), FeatureParams::Crater(50, 50, 10));
  // Post (28, 25) stands at (56, 50), 6 m from the centre: on the rim (1.5 m).
  EXPECT_DOUBLE_EQ(t.ElevationAt(56, 50), 11.5);
  ASSERT_TRUE(t.SetPostElevation(28, 25, 14.0f).ok());
  EXPECT_DOUBLE_EQ(t.GroundElevationAt(56, 50), 14.0);
  EXPECT_DOUBLE_EQ(t.ElevationAt(56, 50), 15.5);
  // Halfway to the next post the ground rose by 2 m and the crater stays 1.5 m above it.
  EXPECT_NEAR(t.ElevationAt(57, 50), 12.0 + 1.5, 1e-9);
  EXPECT_FALSE(t.SetPostElevation(51, 0, 1.0f).ok());
  EXPECT_FALSE(t.SetPostElevation(0, 0, NAN).ok());
}

TEST(TerrainFeatures, SoilAtAnswersTheMaterialOfTheFeatureThatCovers) {
  HeightGrid ground(51, 2.0, 0.0f, Material::kGrass);
  ground.set_soil(ground.SquareAt(60, 60), ground.HalfAt(60, 60), Material::kSand);
  Terrain t(std::move(ground));
  ExpectAdded(t, Id(1), FeatureParams::Crater(30, 30, 8, Material::kRock));
  ExpectAdded(t, Id(2), FeatureParams::Berm(60, 60, 0, 20, 6, 2));  // takes the sand
  ExpectAdded(t, Id(3), FeatureParams::Berm(36, 20, kPi / 2, 20, 4, 3, Material::kConcrete));
  EXPECT_EQ(t.Find(Id(2))->material(), Material::kSand);
  EXPECT_EQ(t.SoilAt(30, 30), Material::kRock);      // crater floor
  EXPECT_EQ(t.SoilAt(25, 30), Material::kRock);      // crater rim
  EXPECT_EQ(t.SoilAt(70, 60), Material::kSand);      // berm from the ground at its start
  EXPECT_EQ(t.SoilAt(36, 30), Material::kConcrete);  // the taller berm over the crater's rim
  EXPECT_EQ(t.SoilAt(90, 90), Material::kGrass);
}

TEST(TerrainFeatures, ParamsRebuildTheIdenticalFeature) {
  const HeightGrid ground = SlopedGround();
  for (const auto& p : MixedFeatures()) {
    auto made = MakeFeature(Id(7), p, ground);
    ASSERT_TRUE(made.ok()) << made.error().message;
    auto again = MakeFeature(Id(7), made.value()->params(), ground);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.value()->params(), p);
    EXPECT_EQ(again.value()->material(), made.value()->material());
    for (double x = 60; x < 130; x += 0.9) {
      for (double z = 60; z < 130; z += 0.9) {
        EXPECT_EQ(made.value()->OffsetAboveGround(x, z), again.value()->OffsetAboveGround(x, z));
      }
    }
  }
}

// ---- Rectangular terrains: features at the far x and far z edges ----

namespace rect {

// nx x nz posts 2 m apart, rising 0.5 m per post along x and 0.2 along z.
HeightGrid Sloped(int nx, int nz) {
  std::vector<float> posts;
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) posts.push_back(static_cast<float>(0.5 * i + 0.2 * j));
  }
  return HeightGrid(nx, nz, 2.0, std::move(posts));
}

// The squares whose closed rectangle touches `b`.
bool Touches(SquareIndex s, const Rect& b) {
  const double x0 = s.i * 2.0, z0 = s.j * 2.0;
  return x0 <= b.max_x && x0 + 2 >= b.min_x && z0 <= b.max_z && z0 + 2 >= b.min_z;
}

}  // namespace rect

TEST(TerrainRectangle, FeaturesNearTheFarCornerAreIndexedInTheRightSquares) {
  // 80 m x 30 m and 30 m x 80 m.
  for (const bool wide : {true, false}) {
    SCOPED_TRACE(wide ? "wide" : "tall");
    Terrain t(wide ? rect::Sloped(41, 16) : rect::Sloped(16, 41));
    const double sx = t.ground().size_x_m(), sz = t.ground().size_z_m();
    // A crater 2 m deep whose rim touches the far x and far z edges exactly.
    const double cx = sx - 5.5, cz = sz - 5.5;
    ExpectAdded(t, Id(1), FeatureParams::DeepCrater(cx, cz, 5.5, 2.0));
    const Rect b = t.Find(Id(1))->Bounds();
    EXPECT_DOUBLE_EQ(b.max_x, sx);
    EXPECT_DOUBLE_EQ(b.max_z, sz);
    int listed = 0;
    for (int j = 0; j < t.ground().squares_z(); ++j) {
      for (int i = 0; i < t.ground().squares_x(); ++i) {
        const bool touches = rect::Touches({i, j}, b);
        ASSERT_EQ(t.FeaturesInSquare({i, j}).size(), touches ? 1u : 0u) << i << "," << j;
        if (!touches) {
          ASSERT_EQ(t.SquareBits({i, j}), 0) << i << "," << j;
        }
        listed += touches;
      }
    }
    EXPECT_EQ(listed, 6 * 6);  // 11 m from the far edges: 6 squares of 2 m
    // The surface at the far corner is the crater's rim's foot: the ground.
    EXPECT_NEAR(t.ElevationAt(sx, sz), t.GroundElevationAt(sx, sz), 1e-9);
    EXPECT_LT(t.ElevationAt(cx, cz), t.GroundElevationAt(cx, cz));  // the bowl
    EXPECT_TRUE(t.FeatureBitAt(cx, cz));
    EXPECT_FALSE(t.FeatureBitAt(1, 1));
    EXPECT_EQ(t.FeaturesNear(sx, sz).size(), 1u);
    // Past the far z edge (but inside a square of the longer side) is off the terrain.
    auto s = t.Add(Id(2), FeatureParams::Crater(cx, sz - 5, 5.5));
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("leaves the terrain"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(fmt::format("[0, {}] x [0, {}] m", sx, sz)), std::string::npos)
        << s.error().message;
    s = t.Add(Id(2), FeatureParams::Crater(sx - 5, cz, 5.5));  // past the far x edge
    ASSERT_FALSE(s.ok());
    s = t.Add(Id(2), FeatureParams::Crater(sz + 1, sx + 1, 1));  // the axes swapped
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(t.feature_count(), 1u);
    // A berm along the far z edge, a ditch along the far x edge.
    ExpectAdded(t, Id(3), FeatureParams::Berm(4, sz - 4, 0, sx - 8, 6, 2));
    EXPECT_GT(Above(t, sx / 2, sz - 4), 1.9);
    ExpectAdded(t, Id(4), FeatureParams::Ditch({{sx - 4, 4, 1, 6}, {sx - 4, sz - 16, 1, 6}}, 1.0));
    EXPECT_LT(Above(t, sx - 4, 8), -0.9);
    ASSERT_TRUE(t.Remove(Id(1)).ok());
    for (const Feature* f : t.FeaturesNear(sx, sz)) EXPECT_NE(f->id(), Id(1));
    EXPECT_EQ(t.ElevationAt(sx, sz), t.GroundElevationAt(sx, sz));
  }
}

TEST(TerrainRectangle, PostsSoilsAndBladeWorkAreBoundedPerAxis) {
  Terrain t(rect::Sloped(7, 4));  // 12 m x 6 m
  EXPECT_TRUE(t.SetPostElevation(6, 3, 9.0f).ok());
  EXPECT_DOUBLE_EQ(t.ElevationAt(12, 6), 9.0);
  EXPECT_EQ(t.ground().posts().back(), 9.0f);
  auto s = t.SetPostElevation(7, 0, 1.0f);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("outside the 7 x 4 grid"), std::string::npos)
      << s.error().message;
  EXPECT_FALSE(t.SetPostElevation(0, 4, 1.0f).ok());
  EXPECT_FALSE(t.SetPostElevation(4, 6, 1.0f).ok());  // fits a 7 x 7 grid, not this one
  EXPECT_TRUE(t.SetSoil({5, 2}, TriangleHalf::kUpper, Material::kRock).ok());
  EXPECT_EQ(t.SoilAt(11.9, 5.9), Material::kRock);
  s = t.SetSoil({2, 5}, TriangleHalf::kUpper, Material::kRock);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("outside the 6 x 3 squares"), std::string::npos)
      << s.error().message;
  // Blade work at the far corner post, keyed j * posts_x + i.
  ExpectAdded(t, Id(1), FeatureParams::EarthMove({{6, 3, 500}, {0, 3, -250}, {6, 0, 100}}));
  EXPECT_EQ(t.BladeDeltaMm(6, 3), 500);
  EXPECT_EQ(t.BladeDeltaMm(0, 3), -250);
  EXPECT_EQ(t.BladeDeltaMm(6, 0), 100);
  EXPECT_EQ(t.BladeDeltaMm(3, 6), 0);  // off the grid
  EXPECT_FLOAT_EQ(t.ground().post(6, 3), 9.5f);
  const std::vector<float> bare = t.BarePosts();
  EXPECT_EQ(bare[3 * 7 + 6], 9.0f);
  EXPECT_FLOAT_EQ(bare[3 * 7 + 0], t.ground().post(0, 3) + 0.25f);
  auto off = t.Add(Id(2), FeatureParams::EarthMove({{2, 4, 10}}));
  ASSERT_FALSE(off.ok());
  EXPECT_NE(off.error().message.find("post (2, 4) is outside the 7 x 4 grid"), std::string::npos)
      << off.error().message;
  t.RemoveAll();
  EXPECT_EQ(t.ground().post(6, 3), 9.0f);
  EXPECT_EQ(t.BladeDeltaMm(6, 3), 0);
}

}  // namespace
}  // namespace dt
