// Tests the live view's vehicles from VehicleState PDUs (view/shared_vehicle_source.h): a
// node's vehicle appears under its owner's name, is dead reckoned between states, is marked dead
// from its appearance and disappears when its owner removes it.
#include "view/shared_vehicle_source.h"

#include <gtest/gtest.h>

#include "transport/test/test_bus_config.h"
#include "transport/transport.h"

namespace dt {
namespace {

constexpr uint8_t kExercise = 3;

TEST(SharedVehicleSource, ANodesVehicleIsDrawnDeadReckonedMarkedDeadAndRemoved) {
  const Terrain terrain(HeightGrid(65, 10.0, 2.0f, Material::kDirt));
  auto transport = MakeTransport("memq://", kExercise);
  PduBus owner_bus(*transport, testing::TestBusConfig({1, 1}, kExercise, 640));
  PduBus view_bus(*transport, testing::TestBusConfig({1, 50}, kExercise, 640));
  SharedVehicleSource source(view_bus, {{{1, 1}, "node-1"}}, {});

  VehicleStateFields s;
  s.id = {1, 1, 1};
  s.type = EntityTypeOfVehicle("tank").value();
  s.location_m = {100.0, 2.0, 300.0};
  s.velocity_mps = {10.0, 0.0, 0.0};
  s.heading_rad = 0.0;
  s.algorithm = DeadReckoningAlgorithm::kFpw;
  source.Tick(terrain, 0.0);
  ASSERT_TRUE(owner_bus.Publish(ToVehicleState(s)).ok());
  ASSERT_TRUE(transport->HandleTimeout(0).ok());
  source.Tick(terrain, 1.0);  // one second after the state arrived: 10 m further east
  auto v = source.Vehicles();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].owner, "node-1");
  EXPECT_EQ(v[0].id, "node-1/1:1:1");
  EXPECT_EQ(v[0].type, "tank");
  EXPECT_NEAR(v[0].x_m, 110.0, 1e-9);
  EXPECT_NEAR(v[0].z_m, 300.0, 1e-9);
  EXPECT_DOUBLE_EQ(v[0].speed_mps, 10.0);
  EXPECT_TRUE(v[0].alive);

  s.velocity_mps = {0.0, 0.0, 0.0};
  s.appearance = appearance::kDestroyed;
  ASSERT_TRUE(owner_bus.Publish(ToVehicleState(s)).ok());
  ASSERT_TRUE(transport->HandleTimeout(0).ok());
  source.Tick(terrain, 1.5);
  v = source.Vehicles();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_FALSE(v[0].alive);

  s.appearance |= appearance::kDeactivated;
  ASSERT_TRUE(owner_bus.Publish(ToVehicleState(s)).ok());
  ASSERT_TRUE(transport->HandleTimeout(0).ok());
  source.Tick(terrain, 2.0);
  EXPECT_TRUE(source.Vehicles().empty());
}

}  // namespace
}  // namespace dt
