// Tests the remote-vehicle table: add, update, remove, conflicts, timeouts, settling on the
// receiver's own terrain.
#include "vehicle/remote_vehicles.h"

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
  // On a bridge the owner's elevation and tilt are kept.
  auto on_bridge = Tank(1, 50, 100);
  on_bridge.location_m[1] = 12.0;
  on_bridge.appearance = appearance::kOnBridge;
  table.Apply({1, 1}, on_bridge, 0.4);
  table.Tick(terrain, 0.4);
  EXPECT_FALSE(v.settled);
  EXPECT_EQ(v.pose.location_m[1], 12.0);
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
