// Blade: cutting at a depth, carrying up to the capacity, setting down when raised, conserving
// soil.
#include "vehicle/blade.h"

#include <cmath>

#include <gtest/gtest.h>

#include "terrain/slump.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {
namespace {

// Drives a blade along +x at speed_mps for `ticks` 100 ms ticks, adding each tick's earth moves
// to the terrain as a node would; returns the posts changed in all.
int64_t Drive(Terrain& t, Blade& blade, double& x, double z, double speed_mps, int ticks,
              uint32_t& number) {
  int64_t changes = 0;
  for (int k = 0; k < ticks; ++k) {
    x += speed_mps * 0.1;
    const auto deltas = blade.Step(t, ShippedFrictionTable(), x, z, 0.0, 5.9);
    for (const auto& piece : SplitEarthMove(deltas)) {
      const Status s = t.Add({1, 1, ++number}, FeatureParams::EarthMove(piece));
      EXPECT_TRUE(s.ok()) << s.error().message;
      changes += static_cast<int64_t>(piece.size());
    }
  }
  return changes;
}

int64_t TotalMm(const Terrain& t) {
  int64_t sum = 0;
  for (int j = 0; j < t.ground().posts_z(); ++j) {
    for (int i = 0; i < t.ground().posts_x(); ++i) sum += t.BladeDeltaMm(i, j);
  }
  return sum;
}

TEST(BladeTest, CutsCarriesAndSetsDownWithoutLosingSoil) {
  Terrain t(HeightGrid(81, 0.5, 0.0f, Material::kDirt));
  Blade blade(BladeOf("bulldozer").value());
  ASSERT_TRUE(blade.Lower(0.2).ok());
  double x = 5.0;
  uint32_t number = 0;
  EXPECT_GT(Drive(t, blade, x, 20.0, 1.5, 30, number), 0);
  // A cut 0.2 m deep along the track behind the blade, soil in the blade or set down ahead.
  EXPECT_NEAR(t.ElevationAt(12.0, 20.0), -0.2, 0.02);
  EXPECT_GT(blade.load_mm(), 0);
  EXPECT_EQ(TotalMm(t) + blade.load_mm(), 0) << "soil made or lost";
  blade.Raise();
  Drive(t, blade, x, 20.0, 1.5, 3, number);
  EXPECT_EQ(blade.load_mm(), 0);
  EXPECT_EQ(TotalMm(t), 0) << "soil made or lost";
  // The pile ahead of where the blade rose stands above the ground.
  double highest = -1.0;
  for (double px = x; px < x + 5.0; px += 0.5) highest = std::max(highest, t.ElevationAt(px, 20.0));
  EXPECT_GT(highest, 0.1);
}

TEST(BladeTest, BeyondTheCapacityTheBladeSpills) {
  Terrain t(HeightGrid(161, 0.5, 0.0f, Material::kDirt));
  Blade blade(BladeOf("bulldozer").value());
  ASSERT_TRUE(blade.Lower(0.5).ok());
  double x = 5.0;
  uint32_t number = 0;
  Drive(t, blade, x, 40.0, 2.0, 150, number);
  const double capacity_mm = blade.spec().capacity_m3 / (0.5 * 0.5) / kPostDeltaUnitM;
  EXPECT_LE(blade.load_mm(), static_cast<int64_t>(capacity_mm));
  EXPECT_GT(blade.LoadM3(0.5), 0.9 * blade.spec().capacity_m3);
  EXPECT_EQ(TotalMm(t) + blade.load_mm(), 0);
}

// The front of a bulldozer's running gear reaches the blade's edge, so the cut must reach the
// surface under the edge: with only the posts behind the edge cut, the gear's front stood on the
// slope up to the next post, still uncut, and the bulldozer climbed the berm it was cutting
// (the earthworks drill: pitched 10 degrees, 8 m in 14 s at a demand of 3 m/s).
TEST(BladeTest, APhysicalBulldozerCutsThroughABermWithoutClimbingIt) {
  // 1 m posts, as the earthworks drill's; a berm across the path at x 39..42 (edges on posts),
  // 1.5 m high on a 3 m base: its sides (56 degrees) are beyond any vehicle's grip.
  Terrain t(HeightGrid(81, 1.0, 0.0f, Material::kGrass));
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::Berm(40.5, 20.0, M_PI / 2, 40.0, 3.0, 1.5)).ok());
  auto type = BuiltInPhysicalType("bulldozer", ShippedFrictionTable());
  ASSERT_TRUE(type);
  auto made = SimulatedVehicle::Make(type.value(), t, 30.0, 40.5, 0.0, VehicleModel::kPhysical);
  ASSERT_TRUE(made) << made.error().message;
  SimulatedVehicle dozer = std::move(made).value();
  Blade blade(BladeOf("bulldozer").value());
  ASSERT_TRUE(blade.Lower(0.0).ok());
  ASSERT_TRUE(dozer.Command(3.0, 0.0).ok());
  uint32_t number = 1;
  double max_pitch_deg = 0.0;
  for (int k = 0; k < 8 * 30; ++k) {  // 8 s at 30 Hz, as a node ticks
    ASSERT_TRUE(dozer.Advance(t, 1.0 / 30).ok());
    const VehiclePose p = dozer.pose();
    max_pitch_deg = std::max(max_pitch_deg, std::abs(p.pitch_rad) * 180.0 / M_PI);
    for (const auto& piece :
         SplitEarthMove(blade.Step(t, ShippedFrictionTable(), p.x_m, p.z_m, p.heading_rad, 5.9))) {
      ASSERT_TRUE(t.Add({1, 1, ++number}, FeatureParams::EarthMove(piece)).ok());
    }
  }
  // Through the berm (its rear, 2.95 m behind its centre, past the far foot) near the speed it
  // was told: at x 51.8 m after 8 s (pitched up to 8.3 degrees by the spill it pushes); with the
  // cut behind the edge alone it was still in the berm, at x 36.6 m.
  EXPECT_GT(dozer.pose().x_m, 46.0) << "pitched up to " << max_pitch_deg << " degrees";
  EXPECT_TRUE(dozer.alive());
  EXPECT_EQ(TotalMm(t) + blade.load_mm(), 0) << "soil made or lost";
}

TEST(BladeTest, BadDepthIsRefusedNamingTheValue) {
  Blade blade(BladeOf("bulldozer").value());
  const Status deep = blade.Lower(0.8);
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.error().message.find("blade depth_m = 0.8 is outside [0, 0.5]"), std::string::npos)
      << deep.error().message;
  EXPECT_FALSE(blade.Lower(std::nan("")).ok());
  EXPECT_FALSE(blade.down());
  EXPECT_FALSE(BladeOf("tank").ok());
}

}  // namespace
}  // namespace dt
