// Impact with a bridge solid (a ramp's side, a pier, rubble) damages by the measure of a landing,
// the speed lost along the contact's normal, against the same thresholds.
#include <cstdio>

#include "terrain/bridge.h"
#include "vehicle/test/vehicle_fixtures.h"

namespace dt::test {
namespace {

constexpr FeatureId kBridge{1, 1, 1};
constexpr double kPi = 3.14159265358979323846;

// A 6 m bridge on flat ground at 10 m: ramp 1 from x 70 to 100, span to 140, ramp 2 to 170, at
// z = 200, 10 m wide (z 195..205); piers 1 m square at x 100 and 140 under both deck edges.
std::unique_ptr<Terrain> BridgeTerrain(bool destroyed = false) {
  auto t = FlatTerrain();
  FeatureParams p = FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 6.0, 6.0);
  if (destroyed) p.status = BridgeStatus::kDestroyed;
  EXPECT_TRUE(t->Add(kBridge, p).ok());
  return t;
}

struct Hit {
  double speed_before_mps = 0.0;  // forward speed the tick before the hull was first blocked
  int blocked_ticks = 0;
  Damage damage = Damage::kNone;
  std::string cause;
};

// Drives north at `speed_mps` into whatever stands across the way at z 195, from far enough
// south to reach that speed.
Hit DriveInto(const Terrain& t, const char* type, double x_m, double speed_mps) {
  const double z0 = speed_mps < 10.0 ? 175.0 : 20.0;
  auto v = PhysicalVehicle::Make(PhysType(type), t, x_m, z0, kPi / 2).value();
  EXPECT_TRUE(v.Command(speed_mps, 0).ok());
  Hit hit;
  for (int i = 0; i < 30 * 40 && hit.blocked_ticks < 60; ++i) {
    const double before = v.speed_mps();
    const PhysicalReport r = v.Advance(t, kTick).value();
    if (r.blocked && hit.blocked_ticks++ == 0) hit.speed_before_mps = before;
    if (!r.cause.empty()) hit.cause = r.cause;
  }
  hit.damage = v.damage();
  std::printf("%s north at x %.1f, %.1f m/s: hit at %.2f m/s, blocked %d ticks, %s %s\n", type, x_m,
              speed_mps, hit.speed_before_mps, hit.blocked_ticks,
              std::string(DamageName(hit.damage)).c_str(), hit.cause.c_str());
  return hit;
}

// Ramp 1 at x 80 stands 2 m above the ground, its underside 1.5 m: a side the tank cannot pass.
TEST(Impact, ATankHittingARampSideAt16MetresASecondIsDestroyed) {
  auto t = BridgeTerrain();
  const Hit hit = DriveInto(*t, "tank", 80, 16.0);
  EXPECT_GT(hit.blocked_ticks, 0);
  EXPECT_GT(hit.speed_before_mps, 15.0);
  EXPECT_EQ(hit.damage, Damage::kDestroyed);
}

// The pier under ramp 1's joint with the span stands at x 99.5..100.5, z 195..196.
TEST(Impact, AJeepHittingAPierAt23AndAHalfMetresASecondIsDestroyed) {
  auto t = BridgeTerrain();
  const Hit hit = DriveInto(*t, "jeep", 100, 23.5);
  EXPECT_GT(hit.blocked_ticks, 0);
  EXPECT_GT(hit.speed_before_mps, 22.0);
  EXPECT_EQ(hit.damage, Damage::kDestroyed);
}

// Between the landing thresholds (jeep 5.5 and 7.5 m/s) the impact immobilises.
TEST(Impact, AnImpactBetweenTheThresholdsImmobilises) {
  auto t = BridgeTerrain();
  const Hit hit = DriveInto(*t, "jeep", 100, 6.5);
  EXPECT_GT(hit.blocked_ticks, 0);
  EXPECT_EQ(hit.damage, Damage::kImmobilised);
}

TEST(Impact, SlowBumpsDoNoHarm) {
  auto t = BridgeTerrain();
  EXPECT_EQ(DriveInto(*t, "tank", 80, 3.0).damage, Damage::kNone);
  EXPECT_EQ(DriveInto(*t, "jeep", 100, 4.0).damage, Damage::kNone);
  EXPECT_EQ(DriveInto(*t, "truck", 100, 4.0).damage, Damage::kNone);
  auto d = BridgeTerrain(true);
  EXPECT_EQ(DriveInto(*d, "tank", 120, 3.0).damage, Damage::kNone);  // the fallen span's rubble
}

TEST(Impact, RubbleHitFastDestroys) {
  auto d = BridgeTerrain(true);
  const Hit hit = DriveInto(*d, "jeep", 120, 20.0);
  EXPECT_GT(hit.blocked_ticks, 0);
  EXPECT_EQ(hit.damage, Damage::kDestroyed);
}

}  // namespace
}  // namespace dt::test
