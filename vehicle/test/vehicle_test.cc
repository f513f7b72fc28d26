#include "vehicle/vehicle.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "vehicle/shipped_friction.h"
#include "vehicle/vehicle_type.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

Vehicle MakeOrDie(VehicleType type, double x, double z, double heading, double size = 100.0) {
  auto v = Vehicle::Make(std::move(type), x, z, heading, size, size);
  if (!v) {
    ADD_FAILURE() << v.error().message;
    std::abort();
  }
  return std::move(v).value();
}

TEST(VehicleType, BuiltInsAreValidAndFoundByName) {
  for (const char* name : {"tank", "truck", "jeep"}) {
    auto t = BuiltInVehicleType(name);
    ASSERT_TRUE(t.ok()) << name;
    EXPECT_EQ(t.value().name, name);
    EXPECT_TRUE(ValidateVehicleType(t.value()).ok()) << name;
    EXPECT_NEAR(t.value().max_pitch_rad, kDefaultMaxPitchDeg * kPi / 180, 1e-12);
    EXPECT_NEAR(t.value().max_roll_rad, kDefaultMaxRollDeg * kPi / 180, 1e-12);
  }
  auto unknown = BuiltInVehicleType("hovercraft");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("hovercraft"), std::string::npos);
}

TEST(VehicleType, ShippedFrictionGivesEveryBuiltInATractionClass) {
  const FrictionTable& t = ShippedFrictionTable();
  for (const VehicleType& type : {TankType(), TruckType(), JeepType()}) {
    EXPECT_NO_THROW((void)t.ClassOf(type.name)) << type.name;
  }
}

TEST(VehicleType, BadValuesAreRefusedByName) {
  VehicleType t = TankType();
  t.length_m = 0.0;
  auto s = ValidateVehicleType(t);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("length_m = 0"), std::string::npos) << s.error().message;
  t = TankType();
  t.width_m = kNan;
  s = ValidateVehicleType(t);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("width_m is not finite"), std::string::npos);
  t = TankType();
  t.max_roll_rad = 2.0;  // beyond a right angle
  EXPECT_FALSE(ValidateVehicleType(t).ok());
  t = TankType();
  t.max_reverse_speed_mps = -1.0;
  EXPECT_FALSE(ValidateVehicleType(t).ok());
  // Built from values: a custom type is accepted.
  VehicleType custom{"apc", 6.0, 3.0, 20.0, 5.0, 0.5, 0.6, 0.5};
  EXPECT_TRUE(ValidateVehicleType(custom).ok());
  EXPECT_TRUE(Vehicle::Make(custom, 50, 50, 0, 100, 100).ok());
}

TEST(Vehicle, MakeRefusesNanOffTerrainAndBadTypes) {
  auto nan = Vehicle::Make(TankType(), kNan, 50, 0, 100, 100);
  ASSERT_FALSE(nan.ok());
  EXPECT_NE(nan.error().message.find("not finite"), std::string::npos);
  EXPECT_FALSE(
      Vehicle::Make(TankType(), 50, 50, std::numeric_limits<double>::infinity(), 100, 100).ok());
  // Centre on the terrain but the front 3.95 m ahead is not.
  auto off = Vehicle::Make(TankType(), 98, 50, 0, 100, 100);
  ASSERT_FALSE(off.ok());
  EXPECT_NE(off.error().message.find("leaves the terrain"), std::string::npos)
      << off.error().message;
  EXPECT_TRUE(Vehicle::Make(TankType(), 96, 50, 0, 100, 100).ok());
  EXPECT_FALSE(Vehicle::Make(TankType(), 50, 98, kPi / 2, 100, 100).ok());
  VehicleType bad = TankType();
  bad.length_m = -1;
  EXPECT_FALSE(Vehicle::Make(bad, 50, 50, 0, 100, 100).ok());
  EXPECT_FALSE(Vehicle::Make(TankType(), 50, 50, 0, kNan, kNan).ok());
}

// On a 100 m x 40 m terrain each axis stops the vehicle at its own edge.
TEST(Vehicle, ARectangularTerrainBoundsEachAxisOnItsOwn) {
  auto made = Vehicle::Make(TankType(), 90, 30, kPi / 2, 100, 40);
  ASSERT_TRUE(made.ok()) << made.error().message;
  EXPECT_EQ(made.value().terrain_size_x_m(), 100.0);
  EXPECT_EQ(made.value().terrain_size_z_m(), 40.0);
  // (50, 38) facing north reaches past z = 40, though it would fit a 100 m square.
  auto off = Vehicle::Make(TankType(), 50, 38, kPi / 2, 100, 40);
  ASSERT_FALSE(off.ok());
  EXPECT_NE(off.error().message.find("leaves the terrain [0, 100] x [0, 40] m"), std::string::npos)
      << off.error().message;
  EXPECT_FALSE(Vehicle::Make(TankType(), 50, 50, 0, 100, 40).ok());
  EXPECT_TRUE(Vehicle::Make(TankType(), 20, 50, kPi / 2, 40, 100).ok());  // 40 m x 100 m
  EXPECT_FALSE(Vehicle::Make(TankType(), 20, 20, 0, 100, kNan).ok());
  // Driving north stops at the north edge, at 40 m, not 100 m.
  Vehicle v = std::move(made).value();
  ASSERT_TRUE(v.Command(5, 0).ok());
  for (int i = 0; i < 40; ++i) ASSERT_TRUE(v.Step(0.5).ok());
  EXPECT_EQ(v.speed_mps(), 0.0);
  EXPECT_NEAR(v.z_m(), 40 - TankType().length_m / 2, 1e-5);
  EXPECT_DOUBLE_EQ(v.x_m(), 90);
  // Turned east, it stops at the east edge.
  Vehicle e = Vehicle::Make(TankType(), 50, 20, 0, 100, 40).value();
  ASSERT_TRUE(e.Command(10, 0).ok());
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(e.Step(0.5).ok());
  EXPECT_NEAR(e.x_m(), 100 - TankType().length_m / 2, 1e-5);
  EXPECT_DOUBLE_EQ(e.z_m(), 20);
}

TEST(Vehicle, CommandIsClampedToTheTypeLimits) {
  Vehicle v = MakeOrDie(TankType(), 50, 50, 0);
  ASSERT_TRUE(v.Command(1000, 10).ok());
  EXPECT_EQ(v.speed_mps(), TankType().max_speed_mps);
  EXPECT_EQ(v.heading_rate_rad_s(), TankType().max_turn_rate_rad_s);
  ASSERT_TRUE(v.Command(-1000, -10).ok());
  EXPECT_EQ(v.speed_mps(), -TankType().max_reverse_speed_mps);
  EXPECT_EQ(v.heading_rate_rad_s(), -TankType().max_turn_rate_rad_s);
  ASSERT_TRUE(v.Command(3, 0.1).ok());
  EXPECT_EQ(v.speed_mps(), 3);
  EXPECT_EQ(v.heading_rate_rad_s(), 0.1);
  // Bad input changes nothing.
  EXPECT_FALSE(v.Command(kNan, 0).ok());
  EXPECT_FALSE(v.Command(1, kNan).ok());
  EXPECT_EQ(v.speed_mps(), 3);
  EXPECT_EQ(v.heading_rate_rad_s(), 0.1);
}

TEST(Vehicle, StepMovesAlongTheHeadingAndReverseMovesBack) {
  Vehicle v = MakeOrDie(JeepType(), 50, 50, kPi / 3);
  ASSERT_TRUE(v.Command(4, 0).ok());
  ASSERT_TRUE(v.Step(2.5).ok());
  EXPECT_NEAR(v.x_m(), 50 + 10 * std::cos(kPi / 3), 1e-12);
  EXPECT_NEAR(v.z_m(), 50 + 10 * std::sin(kPi / 3), 1e-12);
  EXPECT_FALSE(v.reversing());
  EXPECT_NEAR(v.TravelDirectionRad(), kPi / 3, 1e-12);
  ASSERT_TRUE(v.Command(-4, 0).ok());
  EXPECT_TRUE(v.reversing());
  EXPECT_NEAR(v.TravelDirectionRad(), kPi / 3 - kPi, 1e-12);
  ASSERT_TRUE(v.Step(2.5).ok());
  EXPECT_NEAR(v.x_m(), 50, 1e-12);
  EXPECT_NEAR(v.z_m(), 50, 1e-12);
  EXPECT_FALSE(v.Step(-0.1).ok());
  EXPECT_FALSE(v.Step(kNan).ok());
  auto huge = v.Step(1e308);
  ASSERT_FALSE(huge.ok());
  EXPECT_NE(huge.error().message.find("too long"), std::string::npos);
  EXPECT_NEAR(v.x_m(), 50, 1e-12);  // refused steps move nothing
  // Long but finite: stops at the edge.
  ASSERT_TRUE(v.Step(1e100).ok());
  EXPECT_TRUE(std::isfinite(v.x_m()));
  EXPECT_EQ(v.speed_mps(), 0.0);
}

TEST(Vehicle, TurningInPlaceAndAlongAnArc) {
  Vehicle v = MakeOrDie(TankType(), 50, 50, 0);
  ASSERT_TRUE(v.Command(0, 0.5).ok());
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(v.Step(0.1).ok());
  EXPECT_NEAR(v.heading_rad(), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(v.x_m(), 50);
  EXPECT_DOUBLE_EQ(v.z_m(), 50);
  // Half a circle of radius speed / rate = 10 m at 0.5 rad/s: ends 20 m to the left, heading back.
  Vehicle w = MakeOrDie(TankType(), 50, 40, 0);
  ASSERT_TRUE(w.Command(5, 0.5).ok());
  const int steps = 2000;
  for (int i = 0; i < steps; ++i) ASSERT_TRUE(w.Step(kPi / 0.5 / steps).ok());
  EXPECT_NEAR(std::abs(w.heading_rad()), kPi, 1e-9);
  EXPECT_NEAR(w.x_m(), 50, 1e-3);
  EXPECT_NEAR(w.z_m(), 60, 1e-3);
}

TEST(Vehicle, LeavingTheTerrainStopsAtTheEdge) {
  Vehicle v = MakeOrDie(TankType(), 50, 50, 0);
  ASSERT_TRUE(v.Command(10, 0).ok());
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(v.Step(0.1).ok());
  EXPECT_EQ(v.speed_mps(), 0.0);
  EXPECT_NEAR(v.x_m(), 100 - TankType().length_m / 2, 1e-5);
  EXPECT_LE(v.x_m() + TankType().length_m / 2, 100.0);
  EXPECT_DOUBLE_EQ(v.z_m(), 50);
  // A turn that would swing the footprint off the terrain is not made.
  ASSERT_TRUE(v.Command(0, 0.7).ok());
  ASSERT_TRUE(v.Step(1.0).ok());
  EXPECT_DOUBLE_EQ(v.heading_rad(), 0.0);
  EXPECT_EQ(v.heading_rate_rad_s(), 0.0);
  // Backing away works again.
  ASSERT_TRUE(v.Command(-2, 0).ok());
  ASSERT_TRUE(v.Step(1.0).ok());
  EXPECT_NEAR(v.x_m(), 100 - TankType().length_m / 2 - 2, 1e-5);
  // Diagonally into a corner: both axes stay on the terrain.
  Vehicle d = MakeOrDie(JeepType(), 20, 20, -3 * kPi / 4);
  ASSERT_TRUE(d.Command(20, 0).ok());
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(d.Step(0.1).ok());
  for (const GroundPoint& p : d.SixPoints()) {
    EXPECT_GE(p.x_m, 0.0);
    EXPECT_GE(p.z_m, 0.0);
  }
  EXPECT_EQ(d.speed_mps(), 0.0);
}

TEST(Vehicle, DeadVehicleCannotBeDriven) {
  Vehicle v = MakeOrDie(TruckType(), 50, 50, 0);
  ASSERT_TRUE(v.Command(5, 0).ok());
  v.Kill();
  EXPECT_FALSE(v.alive());
  EXPECT_EQ(v.speed_mps(), 0.0);
  auto s = v.Command(5, 0);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("dead"), std::string::npos);
  ASSERT_TRUE(v.Step(1.0).ok());
  EXPECT_DOUBLE_EQ(v.x_m(), 50);
}

TEST(Vehicle, SixPointsAreCornersAndSideCentres) {
  Vehicle v = MakeOrDie(TankType(), 50, 50, kPi / 2);  // heading north: right is east
  const auto p = v.SixPoints();
  const double a = TankType().length_m / 2, r = TankType().width_m / 2;
  EXPECT_NEAR(p[kFrontLeft].x_m, 50 - r, 1e-12);
  EXPECT_NEAR(p[kFrontLeft].z_m, 50 + a, 1e-12);
  EXPECT_NEAR(p[kRearRight].x_m, 50 + r, 1e-12);
  EXPECT_NEAR(p[kRearRight].z_m, 50 - a, 1e-12);
  EXPECT_NEAR(p[kMiddleRight].x_m, 50 + r, 1e-12);
  EXPECT_NEAR(p[kMiddleRight].z_m, 50, 1e-12);
}

}  // namespace
}  // namespace dt
