// Tests the remote-vehicle table: add, update, remove, conflicts, timeouts, settling on the
// receiver's own terrain.
#include "vehicle/remote_vehicles.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace dt {
namespace {

VehicleStateFields Tank(uint16_t entity, double x, double z, double vx = 0) {
  VehicleStateFields s;
  s.id = {1, 1, entity};
  s.type = *EntityTypeOfVehicle("tank");
  s.location_m = {x, 0, z};
  s.velocity_mps = {vx, 0, 0};
  s.algorithm = DeadReckoningAlgorithm::kFpw;
  s.marking = "T";
  return s;
}

Terrain Flat() { return Terrain(HeightGrid(101, 2.0, 5.0f, Material::kDirt)); }

TEST(RemoteVehicles, AddsUpdatesAndRemovesByTheOwnersWord) {
  RemoteVehicles table({});
  const NodeAddress owner{1, 1};
  EXPECT_EQ(table.Apply(owner, Tank(1, 50, 50, 2), 10.0), RemoteApply::kAdded);
  EXPECT_EQ(table.vehicles().size(), 1u);
  // One second later the copy has moved 2 m; the owner says it is at 53: a 1 m correction.
  EXPECT_EQ(table.Apply(owner, Tank(1, 53, 50, 2), 11.0), RemoteApply::kUpdated);
  EXPECT_NEAR(table.vehicles().at({1, 1, 1}).correction_m, 1.0, 1e-12);
  auto gone = Tank(1, 53, 50);
  gone.appearance = appearance::kDeactivated;
  EXPECT_EQ(table.Apply(owner, gone, 12.0), RemoteApply::kRemoved);
  EXPECT_TRUE(table.vehicles().empty());
  EXPECT_EQ(table.Apply(owner, gone, 12.5), RemoteApply::kIgnored);
  EXPECT_EQ(table.removed(), 1u);
}

TEST(RemoteVehicles, AnEntityIdClaimedByASecondSenderIsDroppedAndCounted) {
  RemoteVehicles table({});
  ASSERT_EQ(table.Apply({1, 1}, Tank(7, 50, 50), 0.0), RemoteApply::kAdded);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(table.Apply({2, 2}, Tank(7, 90, 90), 0.1 * i), RemoteApply::kConflict);
  }
  EXPECT_EQ(table.conflicts(), 5u);
  const auto& v = table.vehicles().at({1, 1, 7});
  EXPECT_EQ(v.owner, (NodeAddress{1, 1}));
  EXPECT_EQ(v.state.location_m[0], 50);  // never applied
  // The impostor cannot remove it either.
  auto gone = Tank(7, 50, 50);
  gone.appearance = appearance::kDeactivated;
  EXPECT_EQ(table.Apply({2, 2}, gone, 1.0), RemoteApply::kConflict);
  EXPECT_EQ(table.vehicles().size(), 1u);
}

TEST(RemoteVehicles, DeadReckonsEveryTickAndDropsSilentVehiclesAfterTheTimeout) {
  const Terrain terrain = Flat();
  DeadReckoningThresholds th;  // 5 s heartbeat x 2.4: 12 s
  RemoteVehicles table(th);
  table.Apply({1, 1}, Tank(1, 20, 100, 3), 0.0);
  table.Apply({1, 1}, Tank(2, 150, 100), 6.0);
  EXPECT_TRUE(table.Tick(terrain, 4.0).empty());
  EXPECT_NEAR(table.vehicles().at({1, 1, 1}).pose.location_m[0], 32.0, 1e-12);
  EXPECT_TRUE(table.Tick(terrain, 12.0).empty());  // exactly the timeout: kept
  const auto dropped = table.Tick(terrain, 12.01);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0], (EntityId{1, 1, 1}));
  EXPECT_EQ(table.timed_out(), 1u);
  EXPECT_EQ(table.vehicles().count({1, 1, 2}), 1u);
  EXPECT_EQ(table.count_owned_by({1, 1}), 1u);
  // A silent owner's ID is free again once dropped.
  table.Tick(terrain, 18.1);
  EXPECT_TRUE(table.vehicles().empty());
  EXPECT_EQ(table.Apply({2, 2}, Tank(1, 20, 100), 19.0), RemoteApply::kAdded);
}

TEST(RemoteVehicles, GroundVehiclesSettleOnTheLocalTerrainAndTiltOverItsCrater) {
  Terrain terrain = Flat();
  RemoteVehicles table({});
  // The owner says y = 0 and level (its ground is flat at 0); here the ground is at 5 m.
  table.Apply({1, 1}, Tank(1, 50, 100), 0.0);
  table.Tick(terrain, 0.1);
  const RemoteVehicle& v = table.vehicles().at({1, 1, 1});
  EXPECT_TRUE(v.settled);
  EXPECT_NEAR(v.pose.location_m[1], 5.0, 1e-9);
  EXPECT_NEAR(v.pose.pitch_rad, 0.0, 1e-12);
  // A crater made here (not on the owner's terrain), R = 10 m: its rim (1.5 m high, 6 to 8 m
  // out) lies under the tank's nose, so the tank pitches up while its owner reports it level.
  ASSERT_TRUE(terrain.Add({3, 3, 1}, FeatureParams::Crater(60.95, 100, 10, Material::kDirt)).ok());
  table.Tick(terrain, 0.2);
  EXPECT_NEAR(v.pose.pitch_rad, std::atan2(1.5, 7.9), 1e-6);
  EXPECT_EQ(v.state.pitch_rad, 0.0);
  // Heading north (+z) with its left side on the rim and its right side off the crater: the left
  // side is up, a positive roll (right side down).
  auto north = Tank(1, 69.8, 100);
  north.heading_rad = 1.5707963267948966;
  table.Apply({1, 1}, north, 0.3);
  table.Tick(terrain, 0.3);
  EXPECT_NEAR(v.pose.roll_rad, std::atan2(1.5, 3.7), 1e-6);
  EXPECT_NEAR(v.pose.pitch_rad, 0.0, 1e-9);
  // Falling, the owner's elevation and tilt are kept.
  auto falling = Tank(1, 50, 100);
  falling.location_m[1] = 12.0;
  falling.appearance = appearance::kFalling;
  table.Apply({1, 1}, falling, 0.4);
  table.Tick(terrain, 0.4);
  EXPECT_FALSE(v.settled);
  EXPECT_EQ(v.pose.location_m[1], 12.0);
}

// The lowest point of the footprint of a tank settled at `pose`, against the surface (ground and
// earthworks) under it, on a 9 x 5 grid: positive where the footprint is below the surface.
double SinkM(const Terrain& terrain, const DrPose& pose) {
  const VehicleType tank = BuiltInVehicleType("tank").value();
  const double ax = std::cos(pose.heading_rad), az = std::sin(pose.heading_rad);
  double worst = -INFINITY;
  for (int i = -4; i <= 4; ++i) {
    for (int k = -2; k <= 2; ++k) {
      const double a = tank.length_m / 2 * i / 4, l = tank.width_m / 2 * k / 2;
      const double y =
          pose.location_m[1] + a * std::tan(pose.pitch_rad) + l * std::tan(pose.roll_rad);
      worst = std::max(worst, terrain.ElevationAt(pose.location_m[0] + ax * a - az * l,
                                                  pose.location_m[2] + az * a + ax * l) -
                                  y);
    }
  }
  return worst;
}

// A berm made here across the path of a tank its owner reports on flat ground: the mean of the
// sides' ground put it 0.75 m into the crest; it rests on the crest, level, touching it.
TEST(RemoteVehicles, ARemoteVehicleRestsOnALocalBermsCrestNotInIt) {
  Terrain terrain = Flat();
  // 1.5 m high, 4 m wide at its base, running north-south through x = 50.
  ASSERT_TRUE(
      terrain.Add({3, 3, 1}, FeatureParams::Berm(50, 100, 1.5707963267948966, 30, 4, 1.5)).ok());
  RemoteVehicles table({});
  table.Apply({1, 1}, Tank(1, 50, 100), 0.0);  // heading east, across the berm
  table.Tick(terrain, 0.0);
  const RemoteVehicle& v = table.vehicles().at({1, 1, 1});
  ASSERT_TRUE(v.settled);
  EXPECT_NEAR(v.pose.pitch_rad, 0.0, 1e-9);
  EXPECT_NEAR(v.pose.location_m[1], terrain.ElevationAt(50, 100), 1e-9);
  EXPECT_NEAR(SinkM(terrain, v.pose), 0.0, 1e-6);
  // Anywhere across it, the footprint is nowhere inside the berm (nor inside a crater's rim).
  ASSERT_TRUE(terrain.Add({3, 3, 2}, FeatureParams::Crater(120, 100, 6, Material::kDirt)).ok());
  for (double x = 35; x <= 135; x += 0.5) {
    table.Apply({1, 1}, Tank(1, x, 100), x);
    table.Tick(terrain, x);
    EXPECT_LE(SinkM(terrain, v.pose), 0.05) << "x " << x;
  }
}

// A bridge made here, 6 m high, east-west, ramp 1 from x 40 to 70, span to 110, ramp 2 to 140.
FeatureParams LocalBridge() { return FeatureParams::Bridge(70, 100, 0.0, 10, 30, 40, 30, 6, 6); }

TEST(RemoteVehicles, ARemoteVehicleOnABridgeStandsOnThisNodesDeckOrWhatIsLeftOfIt) {
  Terrain terrain = Flat();
  FeatureParams bridge = LocalBridge();
  ASSERT_TRUE(terrain.Add({3, 3, 1}, bridge).ok());
  RemoteVehicles table({});
  // The owner says it is on the span, 0.3 m off this node's deck (its ground differs).
  auto on_span = Tank(1, 90, 100);
  on_span.appearance = appearance::kOnBridge;
  on_span.location_m[1] = 5.0 + 6.0 - 0.3;
  table.Apply({1, 1}, on_span, 0.0);
  table.Tick(terrain, 0.0);
  const RemoteVehicle& v = table.vehicles().at({1, 1, 1});
  ASSERT_TRUE(v.settled);
  EXPECT_NEAR(v.pose.location_m[1], 11.0, 1e-6);  // the deck's top
  EXPECT_NEAR(v.pose.pitch_rad, 0.0, 1e-9);
  // Half way up ramp 1 it stands on the ramp, pitched by its grade.
  auto on_ramp = Tank(1, 55, 100);
  on_ramp.appearance = appearance::kOnBridge;
  on_ramp.location_m[1] = 8.0;
  table.Apply({1, 1}, on_ramp, 0.1);
  table.Tick(terrain, 0.1);
  EXPECT_NEAR(v.pose.location_m[1], 8.0, 1e-6);
  EXPECT_NEAR(v.pose.pitch_rad, std::atan(6.0 / 30.0), 1e-6);
  // Under the span (the owner drives below it) it is on the ground.
  auto under = Tank(1, 90, 100);
  under.location_m[1] = 5.0;
  table.Apply({1, 1}, under, 0.2);
  table.Tick(terrain, 0.2);
  EXPECT_NEAR(v.pose.location_m[1], 5.0, 1e-9);
  // The span destroyed here, not yet on the owner's terrain: the vehicle the owner still has on
  // its deck is not left in the air 6 m up; it lies on the rubble, below the deck that is gone.
  bridge.status = BridgeStatus::kDestroyed;
  ASSERT_TRUE(terrain.Update({3, 3, 1}, bridge).ok());
  table.Apply({1, 1}, on_span, 0.3);
  table.Tick(terrain, 0.3);
  EXPECT_TRUE(v.settled);
  EXPECT_LT(v.pose.location_m[1], 7.0);
  EXPECT_GE(v.pose.location_m[1], 5.0);
}

TEST(RemoteVehicles, OffTheLocalTerrainTheOwnersPoseIsKept) {
  const Terrain terrain = Flat();  // 200 m
  RemoteVehicles table({});
  table.Apply({1, 1}, Tank(1, 199, 100), 0.0);  // its nose would hang over the edge
  table.Tick(terrain, 0.0);
  EXPECT_FALSE(table.vehicles().at({1, 1, 1}).settled);
  EXPECT_EQ(table.vehicles().at({1, 1, 1}).pose.location_m[1], 0.0);
}

}  // namespace
}  // namespace dt
