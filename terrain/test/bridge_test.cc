#include "terrain/bridge.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "terrain/terrain.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr FeatureId kId{1, 1, 1};

// 300 m x 300 m of flat ground 10 m up, 2 m spacing.
HeightGrid Flat() { return HeightGrid(151, 2.0, 10.0f, Material::kDirt); }

// Joint of ramp 1 and span at (100, 150), running east: ramp 1 x 70..100 up to 6 m, span
// x 100..140 from 6 m to 8 m, ramp 2 x 140..170 down to the ground. 10 m wide: z 145..155.
FeatureParams EastBridge() { return FeatureParams::Bridge(100, 150, 0.0, 10, 30, 40, 30, 6, 8); }

std::unique_ptr<Feature> Make(const FeatureParams& p, const HeightGrid& ground) {
  auto made = MakeBridge(kId, p, ground);
  if (!made) ADD_FAILURE() << made.error().message;
  return made ? std::move(made).value() : nullptr;
}

const Bridge& AsBridge(const Feature& f) { return dynamic_cast<const Bridge&>(f); }

TEST(Bridge, DeckElevationFollowsRampsAndSpan) {
  const HeightGrid ground = Flat();
  auto f = Make(EastBridge(), ground);
  const Bridge& b = AsBridge(*f);
  struct Case {
    double x, expected;
  };
  for (Case c : {Case{70, 10}, {85, 13}, {100, 16}, {120, 17}, {140, 18}, {155, 14}, {170, 10}}) {
    for (double z : {145.0, 150.0, 155.0}) {
      auto deck = b.DeckElevationAt(c.x, z);
      ASSERT_TRUE(deck.has_value()) << c.x << "," << z;
      EXPECT_NEAR(*deck, c.expected, 1e-9) << c.x << "," << z;
    }
  }
  EXPECT_FALSE(b.DeckElevationAt(69.9, 150));
  EXPECT_FALSE(b.DeckElevationAt(170.1, 150));
  EXPECT_FALSE(b.DeckElevationAt(120, 155.1));
  EXPECT_FALSE(b.DeckElevationAt(120, 144.9));
  // Not an earthwork: the terrain's earthwork elevation ignores it.
  EXPECT_FALSE(b.OffsetAboveGround(120, 150));
  EXPECT_TRUE(b.Covers(120, 150));
  EXPECT_FALSE(b.Covers(65, 150));  // hot spot beyond the ramp foot
  EXPECT_EQ(b.material(), Material::kConcrete);
}

TEST(Bridge, CrossPairsAreLevelOnSlopedGroundAtAnyDirection) {
  // Ground rising 0.05 per metre east and 0.1 per metre north.
  std::vector<float> posts(151 * 151);
  for (int j = 0; j < 151; ++j) {
    for (int i = 0; i < 151; ++i) posts[j * 151 + i] = static_cast<float>(0.1 * i + 0.2 * j);
  }
  const HeightGrid ground(151, 2.0, posts);
  FeatureParams p = FeatureParams::Bridge(120, 120, 0.7, 12, 25, 50, 20, 5, 9);
  auto f = Make(p, ground);
  const Bridge& b = AsBridge(*f);
  const double ux = std::cos(0.7), uz = std::sin(0.7);
  auto at = [&](double along, double right) {
    return std::pair{120 + along * ux + right * uz, 120 + along * uz - right * ux};
  };
  auto ground_at = [&](double along) {
    auto [x, z] = at(along, 0);
    return ground.ElevationAt(x, z);
  };
  const std::vector<DeckSection> profile = b.DeckProfile();
  ASSERT_EQ(profile.size(), 4u);
  EXPECT_NEAR(profile[0].elevation_m, ground_at(-25), 1e-9);
  EXPECT_NEAR(profile[1].elevation_m, ground_at(0) + 5, 1e-9);
  EXPECT_NEAR(profile[2].elevation_m, ground_at(50) + 9, 1e-9);
  EXPECT_NEAR(profile[3].elevation_m, ground_at(70), 1e-9);
  for (double along = -24.5; along < 70; along += 2.5) {
    auto [lx, lz] = at(along, -5.999);
    auto [rx, rz] = at(along, 5.999);
    auto left = b.DeckElevationAt(lx, lz);
    auto right = b.DeckElevationAt(rx, rz);
    ASSERT_TRUE(left && right) << along;
    EXPECT_NEAR(*left, *right, 1e-9) << along;
    EXPECT_NEAR(b.ToBridge(rx, rz).along_m, along, 1e-9);
    EXPECT_NEAR(b.ToBridge(rx, rz).right_m, 5.999, 1e-9);
  }
}

TEST(Bridge, HotSpotsAreCentredOnTheRampFeet) {
  const HeightGrid ground = Flat();
  auto f = Make(EastBridge(), ground);
  const Bridge& b = AsBridge(*f);
  const double h = kBridgeHotSpotLengthM / 2;
  EXPECT_EQ(b.HotSpotAt(70 - h, 150), BridgeHotSpot::kRamp1);
  EXPECT_EQ(b.HotSpotAt(70 + h, 155), BridgeHotSpot::kRamp1);
  EXPECT_EQ(b.HotSpotAt(70 - h - 0.01, 150), BridgeHotSpot::kNone);
  EXPECT_EQ(b.HotSpotAt(70 + h + 0.01, 150), BridgeHotSpot::kNone);
  EXPECT_EQ(b.HotSpotAt(70, 155.01), BridgeHotSpot::kNone);
  EXPECT_EQ(b.HotSpotAt(170 + h, 150), BridgeHotSpot::kRamp2);
  EXPECT_EQ(b.HotSpotAt(170 - h, 150), BridgeHotSpot::kRamp2);
  EXPECT_EQ(b.HotSpotAt(120, 150), BridgeHotSpot::kNone);
  EXPECT_TRUE(b.InOuterHotSpot(65, 150));
  EXPECT_FALSE(b.InOuterHotSpot(75, 150));
  EXPECT_TRUE(b.InOuterHotSpot(175, 150));
  EXPECT_FALSE(b.InOuterHotSpot(165, 150));
  EXPECT_NEAR(b.OntoDirectionRad(BridgeHotSpot::kRamp1), 0.0, 1e-12);
  EXPECT_NEAR(b.OntoDirectionRad(BridgeHotSpot::kRamp2), kPi, 1e-12);
  EXPECT_THROW(b.OntoDirectionRad(BridgeHotSpot::kNone), std::invalid_argument);
  const Rect bounds = b.Bounds();
  EXPECT_NEAR(bounds.min_x, 70 - h, 1e-9);
  EXPECT_NEAR(bounds.max_x, 170 + h, 1e-9);
  EXPECT_NEAR(bounds.min_z, 145, 1e-9);
  EXPECT_NEAR(bounds.max_z, 155, 1e-9);
}

TEST(Bridge, DestroyedSpanLiesOnTheGroundAndCarriesNothing) {
  const HeightGrid ground = Flat();
  FeatureParams p = EastBridge();
  p.status = BridgeStatus::kDestroyed;
  auto f = Make(p, ground);
  const Bridge& b = AsBridge(*f);
  EXPECT_TRUE(b.destroyed());
  EXPECT_FALSE(b.DeckElevationAt(100.01, 150));
  EXPECT_FALSE(b.DeckElevationAt(120, 150));
  EXPECT_FALSE(b.DeckElevationAt(139.99, 150));
  EXPECT_NEAR(b.DeckElevationAt(85, 150).value_or(NAN), 13, 1e-9);
  EXPECT_NEAR(b.DeckElevationAt(155, 150).value_or(NAN), 14, 1e-9);
  const std::vector<DeckSection> profile = b.DeckProfile();
  ASSERT_EQ(profile.size(), 6u);
  EXPECT_NEAR(profile[1].elevation_m, 16, 1e-9);
  EXPECT_NEAR(profile[2].along_m, 20, 1e-9);
  EXPECT_NEAR(profile[2].elevation_m, 10, 1e-9);  // the span's middle on the ground
  EXPECT_NEAR(profile[3].elevation_m, 10, 1e-9);
  EXPECT_NEAR(profile[4].elevation_m, 18, 1e-9);
}

TEST(Bridge, MakeRefusesBadParametersAndFootprintsOffTheTerrain) {
  const HeightGrid ground = Flat();
  // Hot spot 1 would start at x = 35 - 30 - 8 = -3.
  auto off = MakeBridge(kId, FeatureParams::Bridge(35, 150, 0, 10, 30, 40, 30, 6, 8), ground);
  ASSERT_FALSE(off.ok());
  EXPECT_NE(off.error().message.find("leaves the terrain"), std::string::npos)
      << off.error().message;
  EXPECT_TRUE(
      MakeBridge(kId, FeatureParams::Bridge(38, 150, 0, 10, 30, 40, 30, 6, 8), ground).ok());
  FeatureParams nan = EastBridge();
  nan.height_m[1] = std::numeric_limits<double>::quiet_NaN();
  auto bad = MakeBridge(kId, nan, ground);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("not finite"), std::string::npos) << bad.error().message;
  FeatureParams zero_width = EastBridge();
  zero_width.width_m = 0;
  EXPECT_FALSE(MakeBridge(kId, zero_width, ground).ok());
  auto crater = MakeBridge(kId, FeatureParams::Crater(100, 100, 5), ground);
  ASSERT_FALSE(crater.ok());
  EXPECT_NE(crater.error().message.find("crater"), std::string::npos);
  // Off the terrain entirely.
  EXPECT_FALSE(
      MakeBridge(kId, FeatureParams::Bridge(400, 150, 0, 10, 30, 40, 30, 6, 8), ground).ok());
}

TEST(Bridge, ParamsRebuildTheSameBridgeAndMaterialFromGroundResolves) {
  const HeightGrid ground = Flat();
  FeatureParams p = EastBridge();
  p.material = Material::kFromGround;
  auto f = Make(p, ground);
  EXPECT_EQ(f->params(), p);
  EXPECT_EQ(f->material(), Material::kDirt);
  auto again = Make(f->params(), ground);
  const auto a = AsBridge(*f).DeckProfile(), b = AsBridge(*again).DeckProfile();
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].elevation_m, b[k].elevation_m);
}

TEST(BridgeInTerrain, OverlappingBridgeIsRefusedAndNothingChanges) {
  Terrain t(Flat());
  ASSERT_TRUE(t.Add(kId, EastBridge()).ok());
  // A north-running bridge crossing the span at x = 120.
  const FeatureId crossing{1, 1, 2};
  auto s = t.Add(crossing, FeatureParams::Bridge(120, 130, kPi / 2, 8, 15, 40, 15, 10, 10));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("overlaps"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find(kId.ToString()), std::string::npos);
  EXPECT_EQ(t.feature_count(), 1u);
  EXPECT_EQ(t.Find(crossing), nullptr);
  // Slightly rotated copy overlapping only a corner region: still refused.
  EXPECT_FALSE(t.Add(crossing, FeatureParams::Bridge(165, 158, 0.3, 6, 10, 20, 10, 2, 2)).ok());
  // A parallel bridge beside it and one end to end (sharing the ramp-foot edge) are accepted.
  EXPECT_TRUE(t.Add({1, 1, 3}, FeatureParams::Bridge(100, 170, 0.0, 10, 30, 40, 30, 6, 8)).ok());
  EXPECT_TRUE(t.Add({1, 1, 4}, FeatureParams::Bridge(200, 150, 0.0, 10, 30, 40, 20, 6, 8)).ok());
  EXPECT_EQ(t.feature_count(), 3u);
  // An update that would move a bridge onto another is refused too.
  FeatureParams moved = EastBridge();
  moved.z_m = 165;
  EXPECT_FALSE(t.Update(kId, moved).ok());
  EXPECT_EQ(t.Find(kId)->params(), EastBridge());
}

TEST(BridgeInTerrain, FeatureBitsCoverTheDeckAndHotSpotsOfARotatedBridge) {
  Terrain t(Flat());
  ASSERT_TRUE(t.Add(kId, FeatureParams::Bridge(140, 130, 2.2, 9, 20, 35, 25, 5, 4)).ok());
  const Bridge& b = AsBridge(*t.Find(kId));
  // Every point the bridge or its hot spots hold has its cell's bit set; points far away do not.
  int inside = 0, outside = 0;
  for (double x = 60; x <= 220; x += 0.37) {
    for (double z = 60; z <= 200; z += 0.41) {
      const bool held = b.OverDeck(x, z) || b.HotSpotAt(x, z) != BridgeHotSpot::kNone;
      if (held) {
        ++inside;
        ASSERT_TRUE(t.FeatureBitAt(x, z)) << x << "," << z;
      }
      const BridgeCoords c = b.ToBridge(x, z);
      if (std::abs(c.right_m) > 4.5 + 1.5 || c.along_m < -20 - 8 - 1.5 ||
          c.along_m > 60 + 8 + 1.5) {
        ++outside;
        ASSERT_FALSE(t.FeatureBitAt(x, z)) << x << "," << z;
      }
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(BridgeInTerrain, SoilUnderADeckIsTheGroundBelow) {
  Terrain t(Flat());
  ASSERT_TRUE(t.Add(kId, EastBridge()).ok());
  // The deck is concrete, but a vehicle driving under the span is on dirt.
  EXPECT_EQ(t.SoilAt(120, 150), Material::kDirt);
  EXPECT_EQ(t.ElevationAt(120, 150), 10.0);
}

TEST(BridgeInTerrain, RepairRestoresTheDeck) {
  Terrain t(Flat());
  FeatureParams p = EastBridge();
  p.status = BridgeStatus::kDestroyed;
  ASSERT_TRUE(t.Add(kId, p).ok());
  EXPECT_FALSE(AsBridge(*t.Find(kId)).DeckElevationAt(120, 150));
  p.status = BridgeStatus::kIntact;
  ASSERT_TRUE(t.Update(kId, p).ok());
  const Bridge& b = AsBridge(*t.Find(kId));
  EXPECT_FALSE(b.destroyed());
  EXPECT_NEAR(b.DeckElevationAt(120, 150).value_or(NAN), 17, 1e-9);
  EXPECT_EQ(b.DeckProfile().size(), 4u);
}

TEST(BridgeInTerrain, GroundChangeUnderAJointMovesTheDeck) {
  Terrain t(Flat());
  ASSERT_TRUE(t.Add(kId, EastBridge()).ok());
  // Post (50, 75) stands at the first joint (100, 150).
  ASSERT_TRUE(t.SetPostElevation(50, 75, 12.0f).ok());
  const Bridge& b = AsBridge(*t.Find(kId));
  EXPECT_NEAR(b.DeckElevationAt(100, 150).value_or(NAN), 18, 1e-9);
  EXPECT_NEAR(b.DeckElevationAt(120, 150).value_or(NAN), 18, 1e-9);  // (18 + 18) / 2
  // The bridge adds nothing to the earthwork elevation, and sets the feature bits it may cover.
  EXPECT_DOUBLE_EQ(t.ElevationAt(120, 150), 10.0);
  EXPECT_TRUE(t.FeatureBitAt(120, 150));
  EXPECT_TRUE(t.FeatureBitAt(63, 150));  // in hot spot 1
  EXPECT_FALSE(t.FeatureBitAt(120, 140));
}

}  // namespace
}  // namespace dt
