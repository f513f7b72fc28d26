// A destroyed vehicle is still a body under gravity: a wreck that tipped over a deck's edge falls
// and comes to rest on what is below it, with one fall event and its bridge tag cleared.
#include <cstdio>

#include "terrain/bridge.h"
#include "vehicle/test/vehicle_fixtures.h"

namespace dt::test {
namespace {

constexpr FeatureId kBridge{1, 1, 1};
constexpr double kPi = 3.14159265358979323846;

// A 6 m bridge on flat ground at 10 m: ramp 1 from x 70 to 100, span to 140, ramp 2 to 170, at
// z = 200, 10 m wide (z 195..205).
std::unique_ptr<Terrain> BridgeTerrain() {
  auto t = FlatTerrain();
  EXPECT_TRUE(t->Add(kBridge, FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 6.0, 6.0)).ok());
  return t;
}

struct Case {
  const char* type;
  double speed_mps, heading_deg;
};

// Creeps off the span's north edge from its centre line, then waits with no command.
void CreepOff(const Case& c) {
  auto t = BridgeTerrain();
  auto v =
      PhysicalVehicle::MakeAt(PhysType(c.type), *t, 120, 200, c.heading_deg * kPi / 180.0, 16.0)
          .value();
  DriveLog l = Drive(*t, v, c.speed_mps, 0, 30,
                     [](const PhysicalVehicle& pv) { return !pv.alive() || pv.z_m() > 215; });
  const DriveLog rest = Drive(*t, v, 0, 0, 20);
  l.fell_off += rest.fell_off;
  l.drove_off += rest.drove_off;
  if (l.cause.empty()) l.cause = rest.cause;
  const double gap = SupportGap(*t, v);
  std::printf(
      "%s off the span at %.1f m/s heading %.1f deg: centre (%.2f, %.2f, %.2f) pitch %.1f roll "
      "%.1f deg; support gap %.3f m; asleep %d; bridge %u; fell-off %d drove-off %d; %s %s\n",
      c.type, c.speed_mps, c.heading_deg, v.x_m(), v.position_m().y(), v.z_m(), Deg(v.pitch_rad()),
      Deg(v.roll_rad()), gap, v.asleep(), v.bridge().number, l.fell_off, l.drove_off,
      std::string(DamageName(v.damage())).c_str(), l.cause.c_str());
  EXPECT_TRUE(v.asleep()) << c.type << " " << c.speed_mps << " m/s: not at rest";
  EXPECT_LE(std::abs(gap), 0.1) << c.type << " " << c.speed_mps << " m/s: not on a support";
  EXPECT_FALSE(v.on_bridge());
  EXPECT_EQ(l.fell_off, 1);
  EXPECT_EQ(l.drove_off, 0);
  // Below the deck's underside (15.5 m): off the span, not hanging on its edge.
  EXPECT_LT(v.position_m().y(), 15.5);
  EXPECT_GT(v.z_m(), 205.0);
}

TEST(Wreck, ATankCreepingOffASpanFallsAndRestsBelow) {
  CreepOff({"tank", 1.0, 97.5});
  CreepOff({"tank", 1.0, 90.1});
  CreepOff({"tank", 3.0, 90.0});
}

TEST(Wreck, TrucksAndJeepsDrivenOffASpanFallAndRestBelow) {
  CreepOff({"truck", 5.0, 90.0});
  CreepOff({"jeep", 5.0, 90.0});
  CreepOff({"truck", 1.0, 95.0});
  CreepOff({"jeep", 1.0, 95.0});
}

}  // namespace
}  // namespace dt::test
