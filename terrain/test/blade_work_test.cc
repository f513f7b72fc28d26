// Blade work: the post-delta layer (order independence, removal), slumping (volume conservation,
// the angle of repose), earth move validation, the file format and the repose table.
#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "terrain/friction_table.h"
#include "terrain/random_terrain.h"
#include "terrain/slump.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"
#include "terrain/terrain_file.h"

namespace dt {
namespace {

HeightGrid Ground(uint64_t seed) {
  return MakeRandomTerrain(
      {.posts_x = 33, .posts_z = 33, .spacing_m = 2.0, .relief_m = 6.0, .seed = seed});
}

std::vector<uint32_t> PostBits(const Terrain& t) {
  std::vector<uint32_t> bits;
  for (float y : t.ground().posts()) bits.push_back(std::bit_cast<uint32_t>(y));
  return bits;
}

// A random earth move of up to 40 posts inside a 12 x 12 window of the 33 x 33 grid.
FeatureParams RandomEarthMove(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> corner(0, 33 - 12), offset(0, 11), count(1, 40);
  std::uniform_int_distribution<int> delta(-800, 800);
  const int i0 = corner(rng), j0 = corner(rng);
  std::vector<PostDelta> deltas;
  const int n = count(rng);
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<uint16_t>(i0 + offset(rng));
    const auto j = static_cast<uint16_t>(j0 + offset(rng));
    int d = delta(rng);
    if (d == 0) d = 1;
    if (std::none_of(deltas.begin(), deltas.end(),
                     [&](const PostDelta& p) { return p.i == i && p.j == j; })) {
      deltas.push_back({i, j, d});
    }
  }
  return FeatureParams::EarthMove(std::move(deltas));
}

TEST(BladeWorkTest, EarthMovesGiveTheSameGroundAndDigestInEveryOrder) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE(fmt::format("seed {}", seed));
    std::mt19937_64 rng(seed);
    std::vector<std::pair<FeatureId, FeatureParams>> changes;
    for (uint32_t k = 1; k <= 25; ++k) changes.push_back({{1, 2, k}, RandomEarthMove(rng)});
    // Earthworks draped on the moved ground, among the earth moves.
    changes.push_back({{3, 1, 1}, FeatureParams::Crater(30.0, 30.0, 6.0)});
    changes.push_back({{3, 1, 2}, FeatureParams::Berm(20.0, 40.0, 0.4, 20.0, 4.0, 1.5)});
    changes.push_back({{3, 1, 3}, FeatureParams::DeepCrater(45.0, 20.0, 5.0, 1.0)});
    Terrain reference(Ground(seed));
    for (const auto& [id, p] : changes) ASSERT_TRUE(reference.Add(id, p).ok());
    const auto digest = ComputeDigest(reference);
    const auto posts = PostBits(reference);
    for (int order = 0; order < 6; ++order) {
      std::shuffle(changes.begin(), changes.end(), rng);
      Terrain t(Ground(seed));
      for (const auto& [id, p] : changes) ASSERT_TRUE(t.Add(id, p).ok());
      EXPECT_EQ(PostBits(t), posts);
      EXPECT_EQ(ComputeDigest(t), digest);
      EXPECT_EQ(t.ElevationAt(31.3, 29.1), reference.ElevationAt(31.3, 29.1));
    }
    // Every post is the bare post plus the sum of the moves over it, whatever the order.
    for (int j = 0; j < 33; ++j) {
      for (int i = 0; i < 33; ++i) {
        int64_t sum = 0;
        for (const auto& [id, p] : changes) {
          for (const PostDelta& d : p.post_deltas) {
            if (d.i == i && d.j == j) sum += d.delta_mm;
          }
        }
        ASSERT_EQ(reference.BladeDeltaMm(i, j), sum);
        const float expected = sum == 0
                                   ? Ground(seed).post(i, j)
                                   : static_cast<float>(Ground(seed).post(i, j) +
                                                        static_cast<double>(sum) * kPostDeltaUnitM);
        ASSERT_EQ(reference.ground().post(i, j), expected) << i << ", " << j;
      }
    }
  }
}

TEST(BladeWorkTest, RemovingEveryEarthMoveRestoresTheGroundBitForBit) {
  std::mt19937_64 rng(7);
  Terrain t(Ground(7));
  const auto bare = PostBits(t);
  const auto bare_digest = ComputeDigest(t);
  std::vector<FeatureId> ids;
  for (uint32_t k = 1; k <= 30; ++k) {
    ids.push_back({1, 1, k});
    ASSERT_TRUE(t.Add(ids.back(), RandomEarthMove(rng)).ok());
  }
  EXPECT_NE(PostBits(t), bare);
  EXPECT_TRUE(std::ranges::equal(t.BarePosts(), Ground(7).posts()));
  std::shuffle(ids.begin(), ids.end(), rng);
  for (const auto& id : ids) ASSERT_TRUE(t.Remove(id).ok());
  EXPECT_EQ(PostBits(t), bare);
  EXPECT_EQ(ComputeDigest(t), bare_digest);
}

TEST(BladeWorkTest, EarthworksFollowTheMovedGround) {
  Terrain t(HeightGrid(33, 2.0, 1.0f));
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::Berm(32.0, 32.0, 0.0, 20.0, 6.0, 2.0)).ok());
  const double before = t.ElevationAt(32.0, 32.0);
  ASSERT_TRUE(t.Add({1, 1, 2}, FeatureParams::EarthMove({{16, 16, -500}})).ok());
  // The berm stands on the post, lowered half a metre with it.
  EXPECT_NEAR(t.ElevationAt(32.0, 32.0), before - 0.5, 1e-6);
  EXPECT_EQ(t.blade_post_count(), 1u);
}

TEST(BladeWorkTest, BadEarthMovesAreRefusedNamingTheField) {
  Terrain t(HeightGrid(17, 1.0, 0.0f));
  auto refused = [&](const FeatureParams& p, const std::string& fragment) {
    const Status s = t.Add({1, 1, 99}, p);
    ASSERT_FALSE(s.ok()) << fragment;
    EXPECT_NE(s.error().message.find(fragment), std::string::npos) << s.error().message;
  };
  refused(FeatureParams::EarthMove({}), "post_deltas: 0 given, needs 1 to 400");
  refused(FeatureParams::EarthMove({{1, 1, 0}}), "post_deltas[0].delta_mm = 0");
  refused(FeatureParams::EarthMove({{1, 1, 10001}}), "post_deltas[0].delta_mm = 10001");
  refused(FeatureParams::EarthMove({{1, 1, 5}, {1, 1, 6}}), "post_deltas[1] post (1, 1)");
  refused(FeatureParams::EarthMove({{17, 3, 5}}), "post_deltas[0] post (17, 3) is outside the 17");
  refused(FeatureParams::EarthMove({{0, 0, 5}, {60, 0, 5}}), "span 61 x 1 posts");
  FeatureParams unsorted;
  unsorted.type = FeatureType::kEarthMove;
  unsorted.post_deltas = {{2, 2, 5}, {1, 2, 5}};
  refused(unsorted, "must be sorted by (j, i)");
  FeatureParams placed = FeatureParams::EarthMove({{1, 1, 5}});
  placed.x_m = 3.0;
  refused(placed, "does not use x_m");
  std::vector<PostDelta> many;
  for (uint16_t k = 0; k < 401; ++k)
    many.push_back({static_cast<uint16_t>(k % 20), static_cast<uint16_t>(k / 20), 1});
  refused(FeatureParams::EarthMove(many), "401 given");
  FeatureParams crater = FeatureParams::Crater(5, 5, 2);
  crater.post_deltas = {{1, 1, 5}};
  refused(crater, "crater cannot carry post deltas");
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::EarthMove({{1, 1, 5}})).ok());
  const Status update = t.Update({1, 1, 1}, FeatureParams::EarthMove({{1, 1, 6}}));
  ASSERT_FALSE(update.ok());
  EXPECT_NE(update.error().message.find("cannot be updated"), std::string::npos);
  // Nothing refused changed the ground.
  EXPECT_EQ(t.blade_post_count(), 1u);
  EXPECT_EQ(t.BladeDeltaMm(1, 1), 5);
}

TEST(BladeWorkTest, EarthMovesRoundTripThroughEncodingAndFile) {
  std::mt19937_64 rng(3);
  Terrain t(Ground(3));
  for (uint32_t k = 1; k <= 10; ++k) ASSERT_TRUE(t.Add({2, 1, k}, RandomEarthMove(rng)).ok());
  ASSERT_TRUE(t.Add({2, 1, 11}, FeatureParams::Crater(30.0, 30.0, 5.0)).ok());
  ASSERT_TRUE(t.SetPostElevation(4, 4, 2.5f).ok());
  const auto bytes = EncodeTerrainFile(t);
  EXPECT_EQ(bytes[8], 3);
  auto back = DecodeTerrainFile(bytes, "t.dtt");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(ComputeDigest(*back.value()), ComputeDigest(t));
  EXPECT_EQ(PostBits(*back.value()), PostBits(t));
  const FeatureParams p = t.Find({2, 1, 1})->params();
  ByteWriter out;
  EncodeFeatureParams(p, out);
  ByteReader in(out.bytes());
  auto decoded = DecodeFeatureParams(in);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value(), p);
}

void PutVersion(std::vector<uint8_t>& bytes, uint32_t version) {
  for (size_t k = 0; k < 4; ++k) bytes[8 + k] = static_cast<uint8_t>(version >> (8 * k));
  const size_t at = bytes.size() - 8;
  ByteWriter sum;
  sum.U64(XXH3_64bits(bytes.data(), at));
  std::copy(sum.bytes().begin(), sum.bytes().end(), bytes.begin() + static_cast<long>(at));
}

TEST(BladeWorkTest, VersionTwoFilesStillLoadAndCannotHoldEarthMoves) {
  // A version 2 file is a version 3 file without earth moves and with 2 in its version field.
  Terrain t(Ground(4));
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::Ditch({{9, 40, 2, 5}, {30, 40, 1.5, 4}}, 1.0)).ok());
  auto v2 = EncodeTerrainFile(t);
  PutVersion(v2, 2);
  auto loaded = DecodeTerrainFile(v2, "v2.dtt");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(ComputeDigest(*loaded.value()), ComputeDigest(t));
  ASSERT_TRUE(t.Add({1, 1, 2}, FeatureParams::EarthMove({{3, 3, 40}})).ok());
  auto with_move = EncodeTerrainFile(t);
  PutVersion(with_move, 2);
  auto refused = DecodeTerrainFile(with_move, "v2.dtt");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("a version 2 file cannot hold an earth_move"),
            std::string::npos)
      << refused.error().message;
}

double Repose35(Material) { return 35.0 * std::numbers::pi / 180.0; }

TEST(BladeWorkTest, SlumpConservesVolumeAndStopsAtTheAngleOfRepose) {
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE(fmt::format("seed {}", seed));
    std::mt19937_64 rng(seed);
    Terrain t(Ground(seed));
    PostWindow w(t, 4, 4, 24, 24);
    // Piles and holes inside the window, as a blade leaves them.
    std::uniform_int_distribution<int> post(8, 23), amount(-3000, 4000);
    int64_t added = 0;
    for (int k = 0; k < 6; ++k) {
      const int a = amount(rng);
      w.height_mm(post(rng), post(rng)) += a;
      added += a;
    }
    ASSERT_EQ(w.VolumeChangeMm(), added);
    const int sweeps = Slump(w, Repose35, 2000);
    EXPECT_LT(sweeps, 2000) << "the slump did not settle";
    // Soil was moved, never made or lost.
    EXPECT_EQ(w.VolumeChangeMm(), added);
    // No slope out of a changed post is steeper than the angle of repose.
    const auto limit = static_cast<int64_t>(
        std::floor(std::tan(Repose35(Material::kGrass)) * w.spacing_m() / kPostDeltaUnitM));
    for (int j = w.j0(); j < w.j0() + w.rows(); ++j) {
      for (int i = w.i0(); i + 1 < w.i0() + w.columns(); ++i) {
        const bool changed = w.height_mm(i, j) != w.initial_mm(i, j) ||
                             w.height_mm(i + 1, j) != w.initial_mm(i + 1, j);
        if (!changed) continue;
        EXPECT_LE(std::abs(w.height_mm(i, j) - w.height_mm(i + 1, j)),
                  std::max(limit, std::abs(w.initial_mm(i, j) - w.initial_mm(i + 1, j))))
            << i << ", " << j;
      }
    }
    // The slumped window is a valid set of earth moves, conserving volume on the terrain too.
    int64_t sum = 0;
    for (const auto& piece : SplitEarthMove(w.Deltas())) {
      const FeatureParams p = FeatureParams::EarthMove(piece);
      ASSERT_TRUE(ValidateFeatureParams(p).ok()) << ValidateFeatureParams(p).error().message;
      for (const PostDelta& d : piece) sum += d.delta_mm;
    }
    EXPECT_EQ(sum, added);
  }
}

TEST(BladeWorkTest, SplitEarthMoveKeepsEveryDeltaInValidPieces) {
  std::vector<PostDelta> all;
  for (uint16_t j = 0; j < 60; ++j) {
    for (uint16_t i = 0; i < 60; ++i) all.push_back({i, j, (i + j) % 7 + 1});
  }
  const auto pieces = SplitEarthMove(all);
  std::vector<PostDelta> joined;
  for (const auto& piece : pieces) {
    ASSERT_TRUE(ValidateFeatureParams(FeatureParams::EarthMove(piece)).ok());
    joined.insert(joined.end(), piece.begin(), piece.end());
  }
  EXPECT_EQ(joined, all);
}

std::string FrictionToml(const std::string& repose) {
  std::string text = "classes = [\"tracked\"]\n";
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    text += fmt::format("[friction.{}]\ntracked = {{ static = 0.8, dynamic = 0.6 }}\n",
                        MaterialName(static_cast<Material>(m)));
  }
  return text + repose;
}

TEST(BladeWorkTest, ReposeAnglesAreReadAndValidated) {
  const FrictionTable without = FrictionTable::Parse(FrictionToml(""), "t.toml");
  EXPECT_DOUBLE_EQ(without.ReposeRad(Material::kSand), kDefaultReposeDeg * std::numbers::pi / 180);
  std::string repose = "[repose]\n";
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    repose += fmt::format("{} = {}\n", MaterialName(static_cast<Material>(m)), 20 + m);
  }
  const FrictionTable with = FrictionTable::Parse(FrictionToml(repose), "t.toml");
  EXPECT_DOUBLE_EQ(with.ReposeRad(Material::kSand), 23.0 * std::numbers::pi / 180);
  EXPECT_THROW(with.ReposeRad(Material::kFromGround), std::invalid_argument);
  auto refused = [&](const std::string& text, const std::string& fragment) {
    try {
      FrictionTable::Parse(FrictionToml(text), "t.toml");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  std::string bad = repose;
  bad.replace(bad.find("sand = 23"), 9, "sand = 90");
  refused(bad, "repose.sand = 90");
  bad = repose;
  bad.replace(bad.find("sand = 23"), 9, "sand = -1");
  refused(bad, "repose.sand = -1");
  bad = repose;
  bad.erase(bad.find("sand = 23"), 10);
  refused(bad, "repose.sand is missing");
  refused(repose + "lava = 30\n", "repose.lava");
}

}  // namespace
}  // namespace dt
