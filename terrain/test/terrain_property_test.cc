// Properties of Terrain over seeded random grounds and random features of every type, in
// random arrival orders (docs/terrain.md "Composing the surface").
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "terrain/crater.h"
#include "terrain/polyline_earthwork.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
// Seeds of square grounds, and of rectangular ones: wider along x than along z, or the other way.
constexpr uint64_t kSquareSeeds[] = {1, 2, 3, 20260101, 987654321};
constexpr uint64_t kWideSeeds[] = {11, 12};
constexpr uint64_t kTallSeeds[] = {13, 14};
const std::vector<uint64_t> kSeeds = [] {
  std::vector<uint64_t> all(std::begin(kSquareSeeds), std::end(kSquareSeeds));
  all.insert(all.end(), std::begin(kWideSeeds), std::end(kWideSeeds));
  all.insert(all.end(), std::begin(kTallSeeds), std::end(kTallSeeds));
  return all;
}();

// Rolling hills (three random sine waves) plus post noise and a cliff, with random soils. A square
// ground for the square seeds, else one whose sides differ by at least 7 posts.
HeightGrid RandomGround(std::mt19937_64& rng, uint64_t seed) {
  std::uniform_int_distribution<int> posts(17, 65);
  std::uniform_real_distribution<double> spacing(1.0, 5.0), unit(0.0, 1.0);
  int nx = posts(rng), nz = nx;
  const bool wide = std::ranges::count(kWideSeeds, seed) > 0;
  if (wide || std::ranges::count(kTallSeeds, seed) > 0) {
    const int other = posts(rng);
    const int longer = std::max({nx, other, 24}), shorter = std::min({nx, other, longer - 7});
    nx = wide ? longer : shorter;
    nz = wide ? shorter : longer;
  }
  const double s = spacing(rng);
  double amp[3], kx[3], kz[3], phase[3];
  for (int w = 0; w < 3; ++w) {
    amp[w] = 20 * unit(rng);
    kx[w] = 0.2 * unit(rng);
    kz[w] = 0.2 * unit(rng);
    phase[w] = 2 * kPi * unit(rng);
  }
  const int cliff_i = nx / 2;
  std::vector<float> heights(static_cast<size_t>(nx) * nz);
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) {
      double h = 4 * (unit(rng) - 0.5) + (i > cliff_i ? 15.0 : 0.0);
      for (int w = 0; w < 3; ++w) h += amp[w] * std::sin(kx[w] * i + kz[w] * j + phase[w]);
      heights[static_cast<size_t>(j) * nx + i] = static_cast<float>(h);
    }
  }
  HeightGrid ground(nx, nz, s, std::move(heights));
  for (int j = 0; j < nz - 1; ++j) {
    for (int i = 0; i < nx - 1; ++i) {
      for (auto half : {TriangleHalf::kLower, TriangleHalf::kUpper}) {
        ground.set_soil({i, j}, half, static_cast<Material>(1 + rng() % (kMaterialCount - 1)));
      }
    }
  }
  return ground;
}

// A random polyline of 2..6 points from (x, z), turning at most 120 degrees at each joint, with
// per-point sizes drawn by `size`.
template <typename Size>
std::vector<FeaturePoint> RandomPolyline(std::mt19937_64& rng, double x, double z, double size_m,
                                         int max_points, Size size) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = 2 + static_cast<int>(rng() % static_cast<uint64_t>(max_points - 1));
  std::vector<FeaturePoint> pts;
  double heading = 2 * kPi * unit(rng);
  for (int k = 0; k < n; ++k) {
    auto [h, w] = size();
    pts.push_back({x, z, h, w});
    const double step = 1 + unit(rng) * size_m / 6;
    heading += (2 * unit(rng) - 1) * kPi * 2 / 3;
    x += step * std::cos(heading);
    z += step * std::sin(heading);
  }
  return pts;
}

// Random craters (some below the ground, some with rim/floor edits that may lower as well as
// raise; the outer ring stays at the ground so the surface stays continuous), berms, ditches
// (a spoil berm only on straight ones: at the inside of a joint the spoil is not continuous,
// docs/terrain.md), berm lines and areas (water, mud, oil, burnt). Some leave the terrain and
// will be refused.
std::vector<FeatureParams> RandomFeatures(std::mt19937_64& rng, double size_x_m, double size_z_m) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<FeatureParams> out;
  const double size_m = std::min(size_x_m, size_z_m);  // sizes fit the shorter side
  const int count = 20 + static_cast<int>(rng() % 40);
  for (int k = 0; k < count; ++k) {
    const double x = size_x_m * unit(rng), z = size_z_m * unit(rng);
    const uint64_t kind = rng() % 10;
    if (kind < 4) {
      const double r = 0.5 + unit(rng) * std::min(30.0, size_m / 4);
      FeatureParams p =
          FeatureParams::Crater(x, z, r, rng() % 3 == 0 ? Material::kRock : Material::kFromGround);
      if (rng() % 2 == 0) p.height_m[0] = unit(rng) * r / 2;  // below the ground
      const int edits = static_cast<int>(rng() % 6);
      for (int e = 0; e < edits; ++e) {
        p = WithCraterVertexEdit(
            p, {static_cast<uint8_t>(rng() % kCraterSpokes),
                static_cast<uint8_t>(rng() % (kCraterRings - 1)), r * (unit(rng) - 0.3)});
      }
      out.push_back(p);
    } else if (kind < 6) {
      out.push_back(FeatureParams::Berm(x, z, 2 * kPi * (unit(rng) - 0.5),
                                        1 + unit(rng) * size_m / 2, 1 + 19 * unit(rng),
                                        0.2 + 7.8 * unit(rng)));
    } else if (kind < 8) {
      const double run = 0.2 + 2 * unit(rng);
      const bool spoil = rng() % 2 == 0;
      auto pts = RandomPolyline(rng, x, z, size_m, spoil ? 2 : 6, [&] {
        return std::pair{0.2 + 4 * unit(rng), 2 * run + 0.1 + 8 * unit(rng)};
      });
      out.push_back(FeatureParams::Ditch(std::move(pts), run, spoil ? 0.3 + 2 * unit(rng) : 0.0,
                                         spoil ? 1 + 4 * unit(rng) : 0.0,
                                         rng() % 2 ? Material::kDirt : Material::kFromGround));
    } else if (kind < 9) {
      auto pts = RandomPolyline(rng, x, z, size_m, 6, [&] {
        return std::pair{0.2 + 5 * unit(rng), 1 + 12 * unit(rng)};
      });
      out.push_back(FeatureParams::BermLine(std::move(pts)));
    } else {
      // A convex-ish polygon of 3..8 points around (x, z), possibly self-crossing.
      const int n = 3 + static_cast<int>(rng() % 6);
      const double r = 1 + unit(rng) * size_m / 4;
      std::vector<FeaturePoint> pts;
      for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * (i + 0.8 * unit(rng)) / n;
        pts.push_back({x + r * unit(rng) * std::cos(a), z + r * unit(rng) * std::sin(a), 0.0, 0.0});
      }
      pts[0] = {x, z, 0.0, 0.0};
      constexpr Material kKinds[] = {Material::kWater, Material::kMud, Material::kOil,
                                     Material::kBurnt};
      const Material m = kKinds[rng() % 4];
      const double level = m == Material::kWater ? 5 + 20 * unit(rng) : 0.0;
      out.push_back(FeatureParams::Area(std::move(pts), m, level));
    }
  }
  return out;
}

struct World {
  Terrain terrain;
  std::vector<std::pair<FeatureId, FeatureParams>> accepted;
};

World Build(uint64_t seed) {
  std::mt19937_64 rng(seed);
  World w{Terrain(RandomGround(rng, seed)), {}};
  const auto features =
      RandomFeatures(rng, w.terrain.ground().size_x_m(), w.terrain.ground().size_z_m());
  for (size_t k = 0; k < features.size(); ++k) {
    const FeatureId id{3, 4, static_cast<uint32_t>(k + 1)};
    const size_t before = w.terrain.feature_count();
    if (w.terrain.Add(id, features[k]).ok()) {
      w.accepted.emplace_back(id, features[k]);
    } else {
      EXPECT_EQ(w.terrain.feature_count(), before);  // never half-applied
    }
  }
  return w;
}

// Random points in bounds, plus the corners and points on the edges.
std::vector<std::pair<double, double>> SamplePoints(uint64_t seed, const HeightGrid& ground,
                                                    int count) {
  const double sx = ground.size_x_m(), sz = ground.size_z_m();
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> pos_x(0.0, sx), pos_z(0.0, sz);
  std::vector<std::pair<double, double>> out = {{0, 0}, {sx, 0}, {0, sz}, {sx, sz}};
  for (int k = 0; k < count; ++k) {
    out.emplace_back(pos_x(rng), pos_z(rng));
    out.emplace_back(sx, pos_z(rng));
    out.emplace_back(pos_x(rng), 0.0);
  }
  for (int k = 0; k < count / 4; ++k) {
    out.emplace_back(pos_x(rng), sz);
    out.emplace_back(0.0, pos_z(rng));
  }
  return out;
}

TEST(TerrainProperty, SomeFeaturesAreAcceptedAndTheRestRefusedCleanly) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    EXPECT_GE(w.accepted.size(), 5u) << "seed " << seed;
    EXPECT_EQ(w.terrain.feature_count(), w.accepted.size());
  }
}

TEST(TerrainProperty, ElevationIsFiniteEverywhereInBounds) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    for (auto [x, z] : SamplePoints(seed, w.terrain.ground(), 20000)) {
      ASSERT_TRUE(std::isfinite(w.terrain.ElevationAt(x, z))) << seed << ": " << x << "," << z;
    }
  }
}

TEST(TerrainProperty, EveryTypeIsAccepted) {
  std::map<FeatureType, int> seen;
  for (uint64_t seed : kSeeds) {
    for (const auto& [id, p] : Build(seed).accepted) ++seen[p.type];
  }
  for (FeatureType t : {FeatureType::kCrater, FeatureType::kBerm, FeatureType::kDitch,
                        FeatureType::kBermLine, FeatureType::kArea}) {
    EXPECT_GT(seen[t], 0) << FeatureTypeName(t);
  }
}

// The composition rule, recomputed from each feature's own offset: the ground plus the highest
// raise (at least 0) plus the deepest cut (at most 0).
TEST(TerrainProperty, ElevationIsGroundPlusHighestRaisePlusDeepestCut) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    int raised = 0, lowered = 0;
    for (auto [x, z] : SamplePoints(seed, w.terrain.ground(), 20000)) {
      const double ground = w.terrain.GroundElevationAt(x, z);
      const double e = w.terrain.ElevationAt(x, z);
      raised += e > ground;
      lowered += e < ground;
      bool covered = false;
      double raise = 0.0, cut = 0.0;
      for (const Feature* f : w.terrain.FeaturesNear(x, z)) {
        if (auto off = f->OffsetAboveGround(x, z)) {
          covered = true;
          raise = std::max(raise, *off);
          cut = std::min(cut, *off);
        }
      }
      ASSERT_EQ(e, ground + raise + cut) << seed << ": " << x << "," << z;
      // Wherever a feature covers a point, the presence bit is set (vehicles rely on it).
      if (covered) {
        EXPECT_TRUE(w.terrain.FeatureBitAt(x, z)) << seed << ": " << x << "," << z;
      }
    }
    EXPECT_GT(raised, 0) << seed;
    EXPECT_GT(lowered, 0) << seed;
  }
}

// |E(a) - E(b)| across each kind of square edge (vertical, horizontal, diagonal), for points a
// and b 2e-7 m apart. Slopes here stay below ~100 m/m, so a continuous surface moves < 2e-5 m.
void ExpectContinuousAcrossSquareEdges(const Terrain& t, uint64_t seed, const char* what) {
  const double s = t.ground().spacing_m();
  const int mx = t.ground().squares_x(), mz = t.ground().squares_z();
  std::mt19937_64 rng(seed + 17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double eps = 1e-7, tolerance = 1e-4;
  for (int k = 0; k < 4000; ++k) {
    const int i = 1 + static_cast<int>(rng() % (mx - 1));
    const int j = static_cast<int>(rng() % mz);
    const double u = unit(rng);
    const double along = (j + u) * s;
    // Vertical edge x = i * s.
    EXPECT_NEAR(t.ElevationAt(i * s - eps, along), t.ElevationAt(i * s + eps, along), tolerance)
        << what << " seed " << seed << " x edge " << i;
    // Horizontal edge z = iz * s (on a square grid iz = i and jx = j).
    const int iz = 1 + (i - 1) % (mz - 1), jx = j % mx;
    const double along_x = (jx + u) * s;
    EXPECT_NEAR(t.ElevationAt(along_x, iz * s - eps), t.ElevationAt(along_x, iz * s + eps),
                tolerance)
        << what << " seed " << seed << " z edge " << iz;
    // The diagonal of square (i - 1, j): from (x0, z1) to (x1, z0).
    const double d = 0.01 + 0.98 * unit(rng);
    const double x = (i - 1 + d) * s, z = (j + 1 - d) * s;
    EXPECT_NEAR(t.ElevationAt(x - eps, z - eps), t.ElevationAt(x + eps, z + eps), tolerance)
        << what << " seed " << seed << " diagonal " << i - 1 << "," << j;
  }
}

TEST(TerrainProperty, ElevationIsContinuousAcrossSquareEdges) {
  for (uint64_t seed : kSeeds) {
    std::mt19937_64 rng(seed);
    const Terrain bare(RandomGround(rng, seed));
    ExpectContinuousAcrossSquareEdges(bare, seed, "bare ground");
    const World w = Build(seed);
    ExpectContinuousAcrossSquareEdges(w.terrain, seed, "with features");
  }
}

// A square's bits are worked out per column and row when a feature is indexed and per square
// when a removal recomputes them: both ways give the same bits on every square.
TEST(TerrainProperty, BitsRecomputedAfterARemovalMatchBitsIndexed) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    std::mt19937_64 ground_rng(seed);
    Terrain kept(RandomGround(ground_rng, seed));  // every other feature only
    for (size_t k = 0; k < w.accepted.size(); k += 2) {
      ASSERT_TRUE(kept.Add(w.accepted[k].first, w.accepted[k].second).ok());
    }
    std::mt19937_64 again_rng(seed);
    Terrain thinned(RandomGround(again_rng, seed));  // all, then every other one removed
    for (const auto& [id, p] : w.accepted) ASSERT_TRUE(thinned.Add(id, p).ok());
    for (size_t k = 1; k < w.accepted.size(); k += 2) {
      ASSERT_TRUE(thinned.Remove(w.accepted[k].first).ok());
    }
    int featured = 0;
    for (int j = 0; j < kept.ground().squares_z(); ++j) {
      for (int i = 0; i < kept.ground().squares_x(); ++i) {
        ASSERT_EQ(kept.SquareBits({i, j}), thinned.SquareBits({i, j}))
            << seed << ": " << i << "," << j;
        featured += kept.SquareBits({i, j}) != 0;
      }
    }
    EXPECT_GT(featured, 0) << seed;
  }
}

TEST(TerrainProperty, InsertionOrderDoesNotMatter) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    std::mt19937_64 rng(seed ^ 0xabcdef);
    auto shuffled = w.accepted;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    std::mt19937_64 ground_rng(seed);
    Terrain other(RandomGround(ground_rng, seed));
    for (const auto& [id, p] : shuffled) ASSERT_TRUE(other.Add(id, p).ok());
    for (auto [x, z] : SamplePoints(seed, w.terrain.ground(), 10000)) {
      ASSERT_EQ(w.terrain.ElevationAt(x, z), other.ElevationAt(x, z))
          << seed << ": " << x << "," << z;
      ASSERT_EQ(w.terrain.SoilAt(x, z), other.SoilAt(x, z)) << seed << ": " << x << "," << z;
      ASSERT_EQ(w.terrain.FeatureBitAt(x, z), other.FeatureBitAt(x, z));
      ASSERT_EQ(w.terrain.WaterLevelAt(x, z), other.WaterLevelAt(x, z));
    }
    EXPECT_EQ(ComputeDigest(w.terrain), ComputeDigest(other)) << seed;
  }
}

// Every node applies the same changes in its own order, some of them updates (a ditch grown by a
// point, a crater deepened) arriving before or after other features: the surface and the digest
// agree.
TEST(TerrainProperty, ArrivalOrderOfAddsAndUpdatesDoesNotMatter) {
  for (uint64_t seed : kSeeds) {
    const World w = Build(seed);
    std::mt19937_64 rng(seed * 31 + 5);
    std::vector<std::pair<FeatureId, FeatureParams>> finals;
    for (const auto& [id, p] : w.accepted) {
      FeatureParams q = p;
      if (q.type == FeatureType::kCrater && rng() % 2 == 0) q.height_m[0] = q.length_m[0] / 4;
      if (q.type == FeatureType::kBermLine) {
        for (auto& pt : q.points) pt.height_m *= 1.5;
      }
      finals.emplace_back(id, q);
    }
    std::vector<double> reference;
    const auto points = SamplePoints(seed, w.terrain.ground(), 3000);
    std::optional<TerrainDigest> reference_digest;
    for (int order = 0; order < 4; ++order) {
      std::mt19937_64 ground_rng(seed);
      Terrain t(RandomGround(ground_rng, seed));
      std::vector<size_t> idx(w.accepted.size());
      std::iota(idx.begin(), idx.end(), size_t{0});
      std::shuffle(idx.begin(), idx.end(), rng);
      for (size_t i : idx) ASSERT_TRUE(t.Add(w.accepted[i].first, w.accepted[i].second).ok());
      std::shuffle(idx.begin(), idx.end(), rng);
      for (size_t i : idx) {
        // An update may be refused (grown off the terrain); then every order refuses it.
        (void)t.Update(finals[i].first, finals[i].second);
      }
      std::vector<double> here;
      for (auto [x, z] : points) here.push_back(t.ElevationAt(x, z));
      if (order == 0) {
        reference = here;
        reference_digest = ComputeDigest(t);
      } else {
        ASSERT_EQ(here, reference) << seed << " order " << order;
        ASSERT_EQ(ComputeDigest(t), *reference_digest) << seed << " order " << order;
      }
    }
  }
}

TEST(TerrainProperty, UpdatingToTheSameParamsAndRemovingAllRestoreTheSurface) {
  for (uint64_t seed : kSeeds) {
    World w = Build(seed);
    const auto points = SamplePoints(seed, w.terrain.ground(), 3000);
    std::vector<double> before;
    for (auto [x, z] : points) before.push_back(w.terrain.ElevationAt(x, z));
    for (const auto& [id, p] : w.accepted) {
      ASSERT_TRUE(w.terrain.Update(id, w.terrain.Find(id)->params()).ok());
    }
    for (size_t k = 0; k < points.size(); ++k) {
      ASSERT_EQ(w.terrain.ElevationAt(points[k].first, points[k].second), before[k]);
    }
    for (const auto& [id, p] : w.accepted) ASSERT_TRUE(w.terrain.Remove(id).ok());
    for (auto [x, z] : points) {
      ASSERT_EQ(w.terrain.ElevationAt(x, z), w.terrain.GroundElevationAt(x, z));
      ASSERT_FALSE(w.terrain.FeatureBitAt(x, z));
    }
  }
}

}  // namespace
}  // namespace dt
