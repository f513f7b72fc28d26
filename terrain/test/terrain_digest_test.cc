#include "terrain/terrain_digest.h"

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

using test::BuildSample;
using test::SampleFeatures;
using test::SampleGround;

TEST(TerrainDigestTest, InsertionOrderDoesNotMatter) {
  auto features = SampleFeatures();
  const TerrainDigest forward = ComputeDigest(*BuildSample(features));
  std::reverse(features.begin(), features.end());
  EXPECT_EQ(ComputeDigest(*BuildSample(features)), forward);
  std::mt19937 shuffle_rng(17);
  for (int round = 0; round < 5; ++round) {
    std::shuffle(features.begin(), features.end(), shuffle_rng);
    EXPECT_EQ(ComputeDigest(*BuildSample(features)), forward);
  }
  // A feature added and removed again leaves no trace.
  auto t = BuildSample(features);
  ASSERT_TRUE(t->Add({3, 3, 3}, FeatureParams::Crater(40.0, 70.0, 2.0)).ok());
  EXPECT_NE(ComputeDigest(*t), forward);
  ASSERT_TRUE(t->Remove({3, 3, 3}).ok());
  EXPECT_EQ(ComputeDigest(*t), forward);
}

TEST(TerrainDigestTest, EveryKindOfChangeChangesTheDigest) {
  const auto features = SampleFeatures();
  const TerrainDigest base = ComputeDigest(*BuildSample(features));
  std::set<TerrainDigest> seen = {base};
  auto expect_new = [&](const Terrain& t, const char* what) {
    const TerrainDigest d = ComputeDigest(t);
    EXPECT_TRUE(seen.insert(d).second) << what << " gave a digest already seen: " << d.ToHex();
  };
  {
    auto t = BuildSample(features);
    ASSERT_TRUE(t->SetPostElevation(4, 7, t->ground().post(4, 7) + 0.001f).ok());
    expect_new(*t, "one post");
  }
  {
    // Posts are hashed as bit patterns: -0 differs from +0.
    Terrain flat(HeightGrid(9, 10.0));
    const TerrainDigest positive_zero = ComputeDigest(flat);
    ASSERT_TRUE(flat.SetPostElevation(8, 8, -0.0f).ok());
    EXPECT_NE(ComputeDigest(flat), positive_zero);
  }
  {
    auto t = BuildSample(features);
    ASSERT_TRUE(t->SetSoil({6, 2}, TriangleHalf::kUpper, Material::kMud).ok());
    expect_new(*t, "one soil");
  }
  {
    auto t = BuildSample(features);
    ASSERT_TRUE(t->SetSoil({6, 2}, TriangleHalf::kLower, Material::kMud).ok());
    expect_new(*t, "the other half's soil");
  }
  {
    auto t = BuildSample(features);
    FeatureParams moved = features[0].second;
    moved.x_m += 0.5;
    ASSERT_TRUE(t->Update(features[0].first, moved).ok());
    expect_new(*t, "one feature moved");
  }
  {
    auto t = BuildSample(features);
    FeatureParams edited = features[1].second;
    edited.vertex_edits[1].offset_m = -0.25;
    ASSERT_TRUE(t->Update(features[1].first, edited).ok());
    expect_new(*t, "one crater vertex edit");
  }
  {
    auto t = BuildSample(features);
    FeatureParams broken = features[4].second;
    broken.status = BridgeStatus::kDestroyed;
    ASSERT_TRUE(t->Update(features[4].first, broken).ok());
    expect_new(*t, "bridge destroyed");
  }
  {
    // Same parameters under another ID.
    auto renamed = features;
    renamed[2].first.number = 2;
    expect_new(*BuildSample(renamed), "one feature renumbered");
  }
  {
    auto fewer = features;
    fewer.pop_back();
    expect_new(*BuildSample(fewer), "one feature fewer");
  }
  expect_new(Terrain(SampleGround()), "no features");
  expect_new(Terrain(HeightGrid(9, 10.0)), "flat ground");
  expect_new(Terrain(HeightGrid(9, 10.5)), "other spacing");
  expect_new(Terrain(HeightGrid(10, 10.0)), "other size");
}

TEST(TerrainDigestTest, GroundDigestEqualsTheDigestOfABareTerrain) {
  const HeightGrid g = SampleGround();
  EXPECT_EQ(ComputeDigest(g), ComputeDigest(Terrain(g)));
  EXPECT_NE(ComputeDigest(g), ComputeDigest(*BuildSample(SampleFeatures())));
}

// The documented encoding's end for a terrain holding one feature, 7:8:9, after the ground
// bytes in `w`: the count, the ID, the parameters; then the XXH3-128 of it all.
TerrainDigest DigestWithTheOneFeature(const Terrain& t, ByteWriter& w) {
  w.U32(1);
  w.U16(7);
  w.U16(8);
  w.U32(9);
  EncodeFeatureParams(t.Find({7, 8, 9})->params(), w);
  const XXH128_hash_t h = XXH3_128bits(w.bytes().data(), w.bytes().size());
  return TerrainDigest{h.high64, h.low64};
}

TEST(TerrainDigestTest, MatchesTheDocumentedEncoding) {
  // docs/terrain.md "State digest", byte by byte, for a 3 x 3 ground with one crater.
  Terrain t(HeightGrid(3, 4.0, {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.5f}));
  ASSERT_TRUE(t.SetSoil({1, 0}, TriangleHalf::kUpper, Material::kRock).ok());
  const FeatureParams crater = FeatureParams::Crater(4.0, 4.0, 1.0, Material::kDirt);
  ASSERT_TRUE(t.Add({7, 8, 9}, crater).ok());
  ByteWriter w;
  for (char c : std::string("dynterrain state v1")) w.U8(static_cast<uint8_t>(c));
  w.U32(3);
  w.F64(4.0);
  for (float y : {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.5f}) w.F32(y);
  // Squares (0,0), (1,0), (0,1), (1,1); lower then upper; grass is 1, rock is 4.
  for (int soil : {1, 1, 1, 4, 1, 1, 1, 1}) w.U16(static_cast<uint16_t>(soil));
  EXPECT_EQ(ComputeDigest(t), DigestWithTheOneFeature(t, w));
}

TEST(TerrainDigestTest, TheShapeOfTheGridIsPartOfTheDigest) {
  // 36 equal posts each; the soils of 4 x 9 and 9 x 4 are equal in number too.
  const TerrainDigest a = ComputeDigest(HeightGrid(4, 9, 10.0, 2.0f));
  const TerrainDigest b = ComputeDigest(HeightGrid(9, 4, 10.0, 2.0f));
  const TerrainDigest c = ComputeDigest(HeightGrid(6, 6, 10.0, 2.0f));
  EXPECT_NE(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(b, c);
  // The square constructor and a rectangle with equal sides are the same ground.
  EXPECT_EQ(ComputeDigest(HeightGrid(6, 10.0, 2.0f)), c);
}

TEST(TerrainDigestTest, ARectangularGroundMatchesTheDocumentedEncoding) {
  // docs/terrain.md "State digest": a grid that is not square writes 0, posts_x, posts_z where a
  // square one writes its side. A 3 x 2 ground with one crater.
  Terrain t(HeightGrid(3, 2, 4.0, {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.5f}));
  ASSERT_TRUE(t.SetSoil({1, 0}, TriangleHalf::kUpper, Material::kRock).ok());
  ASSERT_TRUE(t.Add({7, 8, 9}, FeatureParams::Crater(4.0, 2.0, 1.0, Material::kDirt)).ok());
  ByteWriter w;
  for (char c : std::string("dynterrain state v1")) w.U8(static_cast<uint8_t>(c));
  w.U32(0);
  w.U32(3);
  w.U32(2);
  w.F64(4.0);
  for (float y : {0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.5f}) w.F32(y);
  // Squares (0,0), (1,0); lower then upper; grass is 1, rock is 4.
  for (int soil : {1, 1, 1, 4}) w.U16(static_cast<uint16_t>(soil));
  EXPECT_EQ(ComputeDigest(t), DigestWithTheOneFeature(t, w));
}

TEST(TerrainDigestTest, HexFormRoundTrips) {
  const TerrainDigest d = ComputeDigest(*BuildSample(SampleFeatures()));
  const std::string hex = d.ToHex();
  ASSERT_EQ(hex.size(), 32u);
  EXPECT_EQ(hex.find_first_not_of("0123456789abcdef"), std::string::npos) << hex;
  EXPECT_EQ(TerrainDigest::FromHex(hex), d);
  EXPECT_EQ(TerrainDigest::FromHex("0000000000000001FFFFFFFFFFFFFFFE"),
            (TerrainDigest{1, 0xFFFFFFFFFFFFFFFEull}));
  EXPECT_EQ((TerrainDigest{0xABCull, 0x1ull}).ToHex(), "0000000000000abc0000000000000001");
  EXPECT_FALSE(TerrainDigest::FromHex(hex.substr(1)));
  EXPECT_FALSE(TerrainDigest::FromHex(hex + "0"));
  EXPECT_FALSE(TerrainDigest::FromHex("g" + hex.substr(1)));
}

}  // namespace
}  // namespace dt

namespace dt {
namespace {

// The remembered digest is the full one after every kind of change, on one terrain and when
// asked of another terrain; asked twice without a change it stays the same.
TEST(TerrainDigesterTest, EqualsTheFullDigestAfterEveryKindOfChange) {
  const auto features = SampleFeatures();
  auto t = BuildSample(features);
  TerrainDigester digester;
  std::set<TerrainDigest> seen;
  auto check = [&](const char* what) {
    const TerrainDigest full = ComputeDigest(*t);
    EXPECT_EQ(digester.Of(*t), full) << what;
    EXPECT_EQ(digester.Of(*t), full) << what << ", asked again";
    seen.insert(full);
  };
  check("at first");
  ASSERT_TRUE(t->Add({3, 3, 3}, FeatureParams::Crater(40.0, 70.0, 2.0)).ok());
  check("a crater added");
  ASSERT_TRUE(t->Add({3, 3, 4}, FeatureParams::EarthMove({{5, 6, 250}, {6, 6, -120}})).ok());
  check("an earth move added");
  FeatureParams moved = features[0].second;
  moved.x_m += 0.5;
  ASSERT_TRUE(t->Update(features[0].first, moved).ok());
  check("a feature moved");
  ASSERT_TRUE(t->SetPostElevation(4, 7, t->ground().post(4, 7) + 0.001f).ok());
  check("one post");
  ASSERT_TRUE(t->SetSoil({6, 2}, TriangleHalf::kUpper, Material::kMud).ok());
  check("one soil");
  ASSERT_TRUE(t->Remove({3, 3, 4}).ok());
  check("the earth move removed");
  ASSERT_TRUE(t->Remove({3, 3, 3}).ok());
  check("the crater removed");
  (void)t->RemoveAt(features[0].second.x_m, features[0].second.z_m);
  check("removed at a point");
  ASSERT_TRUE(t->Add({3, 3, 5}, FeatureParams::EarthMove({{2, 2, 900}})).ok());
  t->RemoveAll();
  check("everything removed");
  EXPECT_GE(seen.size(), 9u);  // the changes were changes
  // Another terrain with another ground: never the first one's remembered answer.
  Terrain other(HeightGrid(9, 10.0));
  EXPECT_EQ(digester.Of(other), ComputeDigest(other));
  EXPECT_EQ(digester.Of(*t), ComputeDigest(*t));
}

}  // namespace
}  // namespace dt
