// Tests of the relief's tile arithmetic and of which tiles a change of the terrain touches.
#include "view/relief_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "terrain/terrain.h"
#include "view/relief_tiles.h"

namespace dt {
namespace {

void ExpectLevelsEndAtThePostSpacing(const ReliefPyramid& p) {
  const int last = p.levels() - 1;
  EXPECT_LE(p.metres_per_pixel(last), p.spacing_m());
  if (last > 0) {
    EXPECT_GT(p.metres_per_pixel(last - 1), p.spacing_m());
  }
  for (int level = 0; level < p.levels(); ++level) {
    const double side = p.side_m(level);
    EXPECT_DOUBLE_EQ(side * std::ldexp(1.0, level), std::max(p.size_x_m(), p.size_z_m()));
    // The tiles cover the terrain, and none lies wholly beyond it.
    EXPECT_GE(p.tiles_x(level) * side, p.size_x_m() - 1e-6);
    EXPECT_LT((p.tiles_x(level) - 1) * side, p.size_x_m());
    EXPECT_GE(p.tiles_z(level) * side, p.size_z_m() - 1e-6);
    EXPECT_LT((p.tiles_z(level) - 1) * side, p.size_z_m());
    EXPECT_GE(p.SampleStride(level), 1);
    // A sample a pixel or more (a post a sample at the finest levels), at most two a pixel.
    const double sample = p.SampleStride(level) * p.spacing_m();
    EXPECT_LE(sample, std::max(p.metres_per_pixel(level), p.spacing_m()) + 1e-9);
    EXPECT_GT(2.0 * sample, std::min(p.metres_per_pixel(level), p.spacing_m()));
  }
}

TEST(ReliefPyramidTest, LevelsRunFromTheWholeWorldToAPixelPerPost) {
  const ReliefPyramid large(50000.0, 50000.0, 10.0);  // 5001^2 posts
  ExpectLevelsEndAtThePostSpacing(large);
  EXPECT_EQ(large.tiles_x(0), 1);
  EXPECT_EQ(large.tiles_x(large.levels() - 1), 1 << (large.levels() - 1));
  EXPECT_EQ(large.SampleStride(0), static_cast<int>(50000.0 / 256 / 10.0));
  const ReliefPyramid wide(3072.0, 2048.0, 2.0);  // not square: fewer rows than columns
  ExpectLevelsEndAtThePostSpacing(wide);
  EXPECT_LT(wide.tiles_z(wide.levels() - 1), wide.tiles_x(wide.levels() - 1));
  const ReliefPyramid small(1000.0, 1000.0, 10.0);  // fits one tile: a single level
  EXPECT_EQ(small.levels(), 1);
  ExpectLevelsEndAtThePostSpacing(small);
  EXPECT_THROW(ReliefPyramid(0.0, 10.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ReliefPyramid(10.0, 10.0, NAN), std::invalid_argument);
}

TEST(ReliefPyramidTest, EveryPointIsInTheTilesOverIt) {
  const ReliefPyramid p(3072.0, 2048.0, 2.0);
  for (int level = 0; level < p.levels(); ++level) {
    for (double x = 0.0; x <= 3072.0; x += 97.3) {
      for (double z = 0.0; z <= 2048.0; z += 101.9) {
        const auto tiles = p.TilesOver(Rect{x, z, x, z}, level);
        ASSERT_FALSE(tiles.empty());
        for (const TileKey& k : tiles) {
          EXPECT_TRUE(p.Valid(k)) << k.ToString();
          EXPECT_TRUE(p.TileRect(k).Contains(x, z)) << k.ToString() << " " << x << " " << z;
        }
      }
    }
  }
  EXPECT_TRUE(p.TilesOver(Rect{4000, 0, 5000, 10}, 0).empty());  // beyond the terrain
}

TEST(ReliefPyramidTest, TileKeysParseAndBadOnesAreNamed) {
  const ReliefPyramid p(3072.0, 2048.0, 2.0);
  auto k = ParseTileKey("2/3/1.png", p);
  ASSERT_TRUE(k.ok()) << k.error().message;
  EXPECT_EQ(k.value(), (TileKey{2, 3, 1}));
  EXPECT_EQ(k.value().ToString(), "2/3/1");
  EXPECT_TRUE(ParseTileKey("0/0/0", p).ok());
  for (const char* bad : {"", "1/2", "1/2/3/4", "a/0/0", "0/0/0.jpg", "-1/0/0", "0/1/0", "2/4/0",
                          "2/0/3", "9/0/0", "1//0"}) {
    auto r = ParseTileKey(bad, p);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error().message.find(bad[0] == '\0' ? "\"\"" : bad), std::string::npos)
        << r.error().message;
  }
}

// 1537 x 1025 posts 2 m apart (3072 x 2048 m): tiles of 3072, 1536, 768 and 384 m.
Terrain FlatTerrain() { return Terrain(HeightGrid(1537, 1025, 2.0, 5.0f)); }

std::set<TileKey> KeysOf(const nlohmann::json& message) {
  std::set<TileKey> out;
  if (message.is_null()) return out;
  const ReliefPyramid p(3072.0, 2048.0, 2.0);
  for (const auto& [k, v] : message["versions"].items()) out.insert(ParseTileKey(k, p).value());
  return out;
}

// Every tile a crater's picture may change, and no other: brute force over every tile of every
// level, by its square against the crater's bounds grown by the level's sample (the change names
// whole squares: up to a square more).
void ExpectTheTilesOver(const ReliefPyramid& p, const Rect& bounds, const std::set<TileKey>& got) {
  for (int level = 0; level < p.levels(); ++level) {
    const double sample = p.SampleStride(level) * p.spacing_m();
    for (int tz = 0; tz < p.tiles_z(level); ++tz) {
      for (int tx = 0; tx < p.tiles_x(level); ++tx) {
        const TileKey k{level, tx, tz};
        const Rect r = p.TileRect(k);
        if (r.Intersects(bounds.Expanded(sample))) {
          EXPECT_TRUE(got.contains(k)) << k.ToString() << " is over the crater";
        }
        if (!r.Intersects(bounds.Expanded(sample + p.spacing_m()))) {
          EXPECT_FALSE(got.contains(k)) << k.ToString() << " is away from the crater";
        }
      }
    }
  }
}

TEST(ReliefTilesTest, ACraterChangesExactlyTheTilesOverItAtEveryLevel) {
  Terrain t = FlatTerrain();
  ReliefTiles tiles(t.ground());
  const ReliefPyramid& p = tiles.pyramid();
  ASSERT_EQ(p.levels(), 4);
  (void)tiles.Track(t);  // the start: a new epoch
  const int64_t epoch = tiles.Version({0, 0, 0});
  EXPECT_TRUE(tiles.Track(t).is_null());  // nothing changed since

  // Inside one tile at every level, away from every edge: one tile a level.
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::Crater(100.0, 150.0, 5.0)).ok());
  const nlohmann::json one = tiles.Track(t);
  ASSERT_FALSE(one.is_null());
  EXPECT_EQ(one["type"], "relief_tiles");
  EXPECT_EQ(one["epoch"], epoch);
  EXPECT_EQ(KeysOf(one), (std::set<TileKey>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}));
  ExpectTheTilesOver(p, t.Find({1, 1, 1})->Bounds(), KeysOf(one));
  EXPECT_GT(tiles.Version({3, 0, 0}), epoch);
  EXPECT_EQ(tiles.Version({3, 1, 0}), epoch);

  // Across the finest level's edge at x = 384 m, and at the corner of four at (768, 768) m.
  ASSERT_TRUE(t.Add({1, 1, 2}, FeatureParams::Crater(384.0, 200.0, 6.0)).ok());
  const nlohmann::json two = tiles.Track(t);
  EXPECT_TRUE(KeysOf(two).contains({3, 0, 0}));
  EXPECT_TRUE(KeysOf(two).contains({3, 1, 0}));
  ExpectTheTilesOver(p, t.Find({1, 1, 2})->Bounds(), KeysOf(two));
  ASSERT_TRUE(t.Add({1, 1, 3}, FeatureParams::Crater(768.0, 768.0, 6.0)).ok());
  const nlohmann::json four = tiles.Track(t);
  for (int level : {2, 3}) {
    for (int tz : {0, 1}) {
      for (int tx : {0, 1}) {
        const int first = level == 2 ? 0 : 1;  // 768 m: the edge after tile 0 (768 m) or 1 (384)
        EXPECT_TRUE(KeysOf(four).contains({level, first + tx, first + tz}))
            << level << " " << tx << " " << tz;
      }
    }
  }
  ExpectTheTilesOver(p, t.Find({1, 1, 3})->Bounds(), KeysOf(four));

  // A removal changes its tiles again; the tiles elsewhere keep their versions.
  const int64_t far = tiles.Version({3, 7, 5});
  const Rect b = t.Find({1, 1, 1})->Bounds();
  ASSERT_TRUE(t.Remove({1, 1, 1}).ok());
  const nlohmann::json gone = tiles.Track(t);
  ExpectTheTilesOver(p, b, KeysOf(gone));
  EXPECT_EQ(tiles.Version({3, 7, 5}), far);
  // The snapshot's description holds every changed tile's version.
  const nlohmann::json d = tiles.Describe();
  EXPECT_EQ(d["levels"], 4);
  EXPECT_EQ(d["versions"]["3/0/0"], tiles.Version({3, 0, 0}));
  EXPECT_FALSE(d["versions"].contains("3/7/5"));

  // Everything at once (the log no longer holds the changes): a new epoch for every tile.
  t.RemoveAll();
  const nlohmann::json all = tiles.Track(t);
  EXPECT_GT(all["epoch"].get<int64_t>(), epoch);
  EXPECT_EQ(tiles.Version({3, 7, 5}), all["epoch"].get<int64_t>());
}

}  // namespace
}  // namespace dt
