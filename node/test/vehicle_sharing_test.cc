// Two nodes' VehicleSharing over one in-process bus: a vehicle driven on one is seen on the other
// within the threshold, removed on the owner's word, dropped when its owner falls silent, and
// not taken over by a third node claiming its entity ID; a physical vehicle's states carry its
// own smooth rates.
#include "node/vehicle_sharing.h"

#include <gtest/gtest.h>

#include "transport/test/test_bus_config.h"
#include "transport/transport.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"

namespace dt {
namespace {

constexpr uint8_t kExercise = 3;
constexpr double kTickS = 1.0 / 30;

PduBusConfig Config(NodeAddress local) { return testing::TestBusConfig(local, kExercise, 640); }

SimulatedVehicle LightTank(const Terrain& terrain, double x, double z) {
  auto type = BuiltInPhysicalType("tank", ShippedFrictionTable());
  auto v = SimulatedVehicle::Make(type.value(), terrain, x, z, 0.0, VehicleModel::kLight);
  return std::move(v).value();
}

class VehicleSharingTest : public ::testing::Test {
 protected:
  VehicleSharingTest()
      : terrain_(HeightGrid(65, 10.0, 2.0f, Material::kDirt)),
        transport_(MakeTransport("memq://", kExercise)),
        bus_a_(*transport_, Config({1, 1})),
        bus_b_(*transport_, Config({2, 2})),
        a_(bus_a_, {1, 1}, {}),
        b_(bus_b_, {2, 2}, {}) {}

  // One tick of both nodes: A's vehicles advance and A sends, the bus delivers, B dead reckons.
  void Tick(double speed_mps, double rate_rad_s, bool a_alive = true) {
    t_ += kTickS;
    if (a_alive) {
      for (auto& v : local_a_) {
        ASSERT_TRUE(v.Command(speed_mps, rate_rad_s).ok());
        ASSERT_TRUE(v.Advance(terrain_, kTickS).ok());
      }
      a_.Tick(local_a_, terrain_, t_);
    }
    ASSERT_TRUE(transport_->HandleTimeout(0).ok());
    b_.Tick({}, terrain_, t_);
  }
  // How far B's copy of A's vehicle 0 is from the truth (x, z: B settles y on its own ground).
  double ErrorM() const {
    const auto& remote = b_.remote().vehicles();
    if (remote.empty()) return 1e9;
    const auto& p = remote.begin()->second.pose;
    const VehiclePose truth = local_a_[0].pose();
    return std::hypot(p.location_m[0] - truth.x_m, p.location_m[2] - truth.z_m);
  }

  Terrain terrain_;
  std::unique_ptr<Transport> transport_;
  PduBus bus_a_, bus_b_;
  VehicleSharing a_, b_;
  std::vector<SimulatedVehicle> local_a_;
  double t_ = 0.0;
};

TEST_F(VehicleSharingTest, ARemoteVehicleFollowsItsOwnerWithinTheThreshold) {
  local_a_.push_back(LightTank(terrain_, 100, 300));
  EXPECT_EQ(a_.AddLocal(local_a_[0]), (EntityId{1, 1, 1}));
  double worst_m = 0.0;
  // 10 s straight at 10 m/s, then 10 s turning at 0.2 rad/s.
  for (int i = 0; i < 600; ++i) {
    Tick(10.0, i < 300 ? 0.0 : 0.2);
    worst_m = std::max(worst_m, ErrorM());
  }
  ASSERT_EQ(b_.remote().vehicles().size(), 1u);
  const RemoteVehicle& seen = b_.remote().vehicles().begin()->second;
  EXPECT_EQ(seen.owner, (NodeAddress{1, 1}));
  EXPECT_EQ(seen.type.name, "tank");
  EXPECT_TRUE(seen.settled);
  EXPECT_NEAR(seen.pose.location_m[1], 2.0, 1e-9);  // on B's ground
  // The owner sends when its own copy is off by 1 m, so B's is never off by much more (one
  // tick's motion of 0.33 m, the light model's speed changes within a tick).
  EXPECT_LT(worst_m, 1.5);
  // Far fewer PDUs than ticks: the straight leg costs little more than its heartbeats.
  EXPECT_LT(a_.sent(), 600u / 10);
  EXPECT_GT(a_.sent(), 4u);
  EXPECT_NE(b_.VehiclesText({}).find("remote 1:1:1 tank owner=1:1"), std::string::npos)
      << b_.VehiclesText({});
  EXPECT_NE(a_.VehiclesText(local_a_).find("local 0 1:1:1 tank owner=1:1"), std::string::npos);
  EXPECT_NE(b_.StatusLines().find("remote_vehicles 1"), std::string::npos);
}

// The owner reports a physical vehicle's own velocities, not differences of its poses: those
// jitter with its fixed internal steps sampled at 33 ms ticks, and a receiver that lost the next
// state dead reckoned their accelerations of tens of m/s^2 (the loss drill saw copies 100 m off).
TEST_F(VehicleSharingTest, APhysicalVehiclesStatesCarryItsOwnSmoothRates) {
  auto type = BuiltInPhysicalType("jeep", ShippedFrictionTable());
  local_a_.push_back(
      SimulatedVehicle::Make(type.value(), terrain_, 300, 300, 0.0, VehicleModel::kPhysical)
          .value());
  a_.AddLocal(local_a_[0]);
  // 2 s to settle and speed up, then 8 s of a steady 6 m/s turn at 0.14 rad/s (radius 43 m:
  // a centripetal acceleration of 0.84 m/s^2).
  double worst_acceleration_mps2 = 0.0;
  for (int i = 0; i < 300; ++i) {
    Tick(6.0, 0.14);
    if (i < 60 || b_.remote().vehicles().empty()) continue;
    const auto& a = b_.remote().vehicles().begin()->second.state.acceleration_mps2;
    worst_acceleration_mps2 = std::max(worst_acceleration_mps2, std::hypot(a[0], a[1], a[2]));
  }
  EXPECT_LT(worst_acceleration_mps2, 3.0);
  // A steady turn is dead reckoned well: about one state a second at most.
  EXPECT_LT(a_.sent(), 20u);
}

// Every built-in type is shared with its own footprint: the bulldozer had no entity type, so
// the other nodes saw its blade work and never the bulldozer.
TEST_F(VehicleSharingTest, EveryBuiltInTypeIsSharedAsItself) {
  const std::vector<std::string> types = {"tank", "truck", "jeep", "bulldozer"};
  for (size_t k = 0; k < types.size(); ++k) {
    auto type = BuiltInPhysicalType(types[k], ShippedFrictionTable());
    ASSERT_TRUE(type) << types[k];
    local_a_.push_back(SimulatedVehicle::Make(type.value(), terrain_,
                                              100.0 + 60.0 * static_cast<double>(k), 300, 0.0,
                                              VehicleModel::kLight)
                           .value());
    EXPECT_EQ(a_.AddLocal(local_a_.back()), (EntityId{1, 1, static_cast<uint16_t>(k + 1)}));
  }
  Tick(0, 0);
  ASSERT_EQ(b_.remote().vehicles().size(), types.size());
  size_t k = 0;
  for (const auto& [id, seen] : b_.remote().vehicles()) {
    EXPECT_EQ(id, (EntityId{1, 1, static_cast<uint16_t>(k + 1)}));
    EXPECT_EQ(seen.type.name, types[k]);
    EXPECT_DOUBLE_EQ(seen.type.length_m, local_a_[k].type().base.length_m) << types[k];
    EXPECT_DOUBLE_EQ(seen.type.width_m, local_a_[k].type().base.width_m) << types[k];
    ++k;
  }
  EXPECT_NE(b_.VehiclesText({}).find("remote 1:1:4 bulldozer owner=1:1"), std::string::npos)
      << b_.VehiclesText({});
}

TEST_F(VehicleSharingTest, RemovalIsSeenAtOnce) {
  local_a_.push_back(LightTank(terrain_, 100, 300));
  a_.AddLocal(local_a_[0]);
  Tick(0, 0);
  ASSERT_EQ(b_.remote().vehicles().size(), 1u);
  a_.RemoveLocal(0, local_a_[0], t_);
  local_a_.clear();
  Tick(0, 0);
  EXPECT_TRUE(b_.remote().vehicles().empty());
  EXPECT_EQ(b_.remote().removed(), 1u);
  EXPECT_EQ(b_.remote().timed_out(), 0u);
}

TEST_F(VehicleSharingTest, ASilentOwnersVehicleIsDroppedAfterTheTimeoutAndNotBefore) {
  local_a_.push_back(LightTank(terrain_, 100, 300));
  a_.AddLocal(local_a_[0]);
  Tick(0, 0);
  // A is killed: nothing more from it. 2.4 heartbeats of 5 s: 12 s.
  int ticks = 0;
  while (!b_.remote().vehicles().empty() && ticks < 30 * 20) {
    Tick(0, 0, /*a_alive=*/false);
    ++ticks;
  }
  EXPECT_NEAR(ticks * kTickS, 12.0, 2 * kTickS);
  EXPECT_EQ(b_.remote().timed_out(), 1u);
}

TEST_F(VehicleSharingTest, AThirdNodeClaimingTheEntityIdIsDroppedAndCounted) {
  local_a_.push_back(LightTank(terrain_, 100, 300));
  a_.AddLocal(local_a_[0]);
  Tick(0, 0);
  PduBus bus_c(*transport_, Config({3, 3}));
  VehicleStateFields forged;
  forged.id = {1, 1, 1};
  forged.type = *EntityTypeOfVehicle("tank");
  forged.location_m = {500, 0, 500};
  forged.marking = "X";
  ASSERT_TRUE(bus_c.Publish(ToVehicleState(forged)).ok());
  Tick(0, 0);
  EXPECT_EQ(b_.remote().conflicts(), 1u);
  EXPECT_LT(ErrorM(), 0.5);  // never applied
  EXPECT_NE(b_.StatusLines().find("vehicle_conflicts 1"), std::string::npos);
}

TEST(OwnerColour, NeighbouringNodesDiffer) {
  EXPECT_NE(OwnerColour({1, 1}), OwnerColour({1, 2}));
  EXPECT_NE(OwnerColour({1, 2}), OwnerColour({1, 3}));
  EXPECT_EQ(OwnerColour({1, 1}), OwnerColour({1, 1}));
}

}  // namespace
}  // namespace dt
