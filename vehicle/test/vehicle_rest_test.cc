// Unit tests of rest: a vehicle with no command that has come to rest sleeps, keeps its pose bit
// for bit, and wakes for a command or a change of the terrain under it, and only then.
#include <cmath>

#include "vehicle/test/vehicle_fixtures.h"

namespace dt::test {
namespace {

bool SamePose(const PhysicalVehicle& a, const Eigen::Vector3d& x, const Eigen::Quaterniond& q) {
  return a.position_m() == x && a.orientation().coeffs() == q.coeffs();
}

TEST(VehicleRest, ParkedVehicleSleepsKeepsItsPoseAndWakesOnACommand) {
  for (const char* name : {"tank", "truck", "jeep"}) {
    auto t = FlatTerrain();
    auto v = PhysicalVehicle::Make(PhysType(name), *t, 150, 150, 0.4).value();
    int ticks_to_sleep = 0;
    Drive(*t, v, 0, 0, 5, [&](const PhysicalVehicle& pv) {
      ++ticks_to_sleep;
      return pv.asleep();
    });
    ASSERT_TRUE(v.asleep()) << name;
    const Eigen::Vector3d x = v.position_m();
    const Eigen::Quaterniond q = v.orientation();
    EXPECT_EQ(v.velocity_mps().norm(), 0.0);
    const PhysicalReport r = v.Advance(*t, 1.0).value();
    EXPECT_EQ(r.steps, 100);  // the time passes, in whole steps, asleep
    Drive(*t, v, 0, 0, 10);
    EXPECT_TRUE(v.asleep());
    EXPECT_TRUE(SamePose(v, x, q));
    // A command that moves it wakes it, and it drives off.
    ASSERT_TRUE(v.Command(5.0, 0.0).ok());
    EXPECT_FALSE(v.asleep());
    Drive(*t, v, 5.0, 0.0, 3);
    const double moved_m = (v.position_m() - x).norm();
    std::printf("%s parked: asleep after %d ticks; commanded 5 m/s, moved %.2f m in 3 s\n", name,
                ticks_to_sleep, moved_m);
    EXPECT_GT(moved_m, 5.0);
    EXPECT_FALSE(v.asleep());
  }
}

TEST(VehicleRest, ACommandOfZeroLeavesItAsleep) {
  auto t = FlatTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 150, 150, 0.0).value();
  Drive(*t, v, 0, 0, 5, [](const PhysicalVehicle& pv) { return pv.asleep(); });
  ASSERT_TRUE(v.asleep());
  ASSERT_TRUE(v.Command(0.0, 0.0).ok());
  EXPECT_TRUE(v.asleep());
}

// Changes elsewhere on the terrain leave a sleeper asleep; one under its hull wakes it, and it
// settles onto what changed.
TEST(VehicleRest, WakesForAChangeUnderItsHullAndNoOther) {
  auto t = FlatTerrain();  // 2 m posts
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 150, 150, 0.3).value();
  Drive(*t, v, 0, 0, 5, [](const PhysicalVehicle& pv) { return pv.asleep(); });
  ASSERT_TRUE(v.asleep());
  const double parked = v.elevation_m();
  ASSERT_TRUE(t->Add(FeatureId{1, 1, 1}, FeatureParams::Crater(250, 250, 8.0)).ok());
  ASSERT_TRUE(t->SetPostElevation(10, 10, 12.0f).ok());
  Drive(*t, v, 0, 0, 1);
  EXPECT_TRUE(v.asleep());
  ASSERT_TRUE(t->Add(FeatureId{1, 1, 2}, FeatureParams::Crater(150, 150, 8.0)).ok());
  (void)v.Advance(*t, kTick).value();
  EXPECT_FALSE(v.asleep());
  Drive(*t, v, 0, 0, 6);
  std::printf("tank asleep at %.3f m; a crater made under it woke it: %.3f m, asleep again %d\n",
              parked, v.elevation_m(), v.asleep());
  EXPECT_GT(v.elevation_m(), parked + 0.3);  // on the crater's rim
  EXPECT_TRUE(v.asleep());
}

// Advanced on another terrain, even one made before, it wakes and meets that terrain.
TEST(VehicleRest, WakesOnAnotherTerrain) {
  auto older = FlatTerrain();
  ASSERT_TRUE(older->Add(FeatureId{1, 1, 1}, FeatureParams::Crater(150, 150, 8.0)).ok());
  auto t = FlatTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 150, 150, 0.3).value();
  Drive(*t, v, 0, 0, 5, [](const PhysicalVehicle& pv) { return pv.asleep(); });
  ASSERT_TRUE(v.asleep());
  const double parked = v.elevation_m();
  (void)v.Advance(*older, kTick).value();
  EXPECT_FALSE(v.asleep());
  Drive(*older, v, 0, 0, 4);
  EXPECT_GT(v.elevation_m(), parked + 0.3);  // on the older terrain's crater rim
}

TEST(VehicleRest, AnImmobilisedVehicleComesToRestAndSleeps) {
  auto t = FlatTerrain();
  auto v = PhysicalVehicle::MakeAt(PhysType("tank"), *t, 100, 100, 0, kGround + 3.0).value();
  Drive(*t, v, 0, 0, 8, [](const PhysicalVehicle& pv) { return pv.asleep(); });
  EXPECT_EQ(v.damage(), Damage::kImmobilised);
  EXPECT_TRUE(v.asleep());
}

// Sliding and falling are not rest: a jeep parked on a slope beyond its grip slides on to the
// foot of the slope, and only sleeps there.
TEST(VehicleRest, ASlidingVehicleDoesNotSleep) {
  auto t = SlopeTerrain(32.0);
  auto v =
      PhysicalVehicle::MakeAt(PhysType("jeep"), *t, 150, 200, 1.5708,
                              10.0 + 50.0 * std::tan(32.0 * 3.14159265358979323846 / 180.0) + 0.3)
          .value();
  double asleep_at_x = 0.0;
  Drive(*t, v, 0, 0, 60, [&](const PhysicalVehicle& pv) {
    asleep_at_x = pv.x_m();
    return pv.asleep();
  });
  std::printf("jeep parked on a 32 deg slope at x 150 m: asleep %d at x %.2f m\n", v.asleep(),
              asleep_at_x);
  EXPECT_LT(v.x_m(), 100.0 + 2.0);  // slid down to the flat
}

}  // namespace
}  // namespace dt::test
