// Unit tests of the physical model: determinism, refusals, slopes, soils, falls.
#include <cstring>
#include <vector>

#include "vehicle/test/vehicle_fixtures.h"

namespace dt::test {
namespace {

struct Sample {
  Eigen::Vector3d x, v, w;
  Eigen::Quaterniond q;
};

std::vector<Sample> RunTank(const Terrain& t) {
  auto v = PhysicalVehicle::Make(PhysType("tank"), t, 60, 100, 0.3).value();
  std::vector<Sample> out;
  for (int i = 0; i < 300; ++i) {
    if (i % 60 == 0) {
      EXPECT_TRUE(v.Command(4.0 + i / 30.0, (i % 120 == 0) ? 0.3 : -0.2).ok());
    }
    EXPECT_TRUE(v.Advance(t, kTick).ok());
    out.push_back({v.position_m(), v.velocity_mps(), v.angular_velocity_rad_s(), v.orientation()});
  }
  return out;
}

TEST(PhysicalVehicle, SameInputsGiveBitIdenticalTrajectories) {
  auto t = FlatTerrain();
  ASSERT_TRUE(t->Add({1, 1, 1}, FeatureParams::Crater(100, 110, 8)).ok());
  ASSERT_TRUE(t->Add({1, 1, 2}, FeatureParams::Berm(130, 90, 1.6, 40, 6, 1.0)).ok());
  const std::vector<Sample> a = RunTank(*t), b = RunTank(*t);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::memcmp(a[i].x.data(), b[i].x.data(), sizeof(double) * 3), 0) << "tick " << i;
    ASSERT_EQ(std::memcmp(a[i].v.data(), b[i].v.data(), sizeof(double) * 3), 0) << "tick " << i;
    ASSERT_EQ(std::memcmp(a[i].w.data(), b[i].w.data(), sizeof(double) * 3), 0) << "tick " << i;
    ASSERT_EQ(std::memcmp(a[i].q.coeffs().data(), b[i].q.coeffs().data(), sizeof(double) * 4), 0)
        << "tick " << i;
  }
  // The run went somewhere: the comparison is not of two vehicles at rest.
  EXPECT_GT((a.back().x - a.front().x).norm(), 20.0);
  std::printf("determinism: %zu ticks, final (x %.6f, y %.6f, z %.6f) in both runs\n", a.size(),
              a.back().x.x(), a.back().x.y(), a.back().x.z());
}

TEST(PhysicalVehicle, InternalStepDoesNotDependOnTheCallersTick) {
  auto t = FlatTerrain();
  auto a = PhysicalVehicle::Make(PhysType("jeep"), *t, 60, 100, 0).value();
  auto b = a;
  auto c = a;
  ASSERT_TRUE(a.Command(10, 0.2).ok());
  ASSERT_TRUE(b.Command(10, 0.2).ok());
  ASSERT_TRUE(c.Command(10, 0.2).ok());
  // 3 s as 75 ticks of 40 ms, as calls of one internal step each, or as 90 ticks of 1/30 s plus
  // what is left: the same fixed steps run, so the trajectories are the same bits.
  constexpr int kSteps = static_cast<int>(3'000'000'000 / kPhysicsStepNs);
  for (int i = 0; i < 75; ++i) ASSERT_TRUE(a.Advance(*t, 0.04).ok());
  for (int i = 0; i < kSteps; ++i) ASSERT_TRUE(b.Advance(*t, kPhysicsStepS).ok());
  int steps = 0;
  for (int i = 0; i < 90; ++i) steps += c.Advance(*t, 1.0 / 30.0).value().steps;
  // 1/30 s is 33 333 333 ns: what is left of the last step waits for the next call.
  EXPECT_EQ(steps, 90 * int64_t{33'333'333} / kPhysicsStepNs);
  steps += c.Advance(*t, 1e-6).value().steps;
  EXPECT_EQ(steps, kSteps);
  for (const PhysicalVehicle* v : {&b, &c}) {
    EXPECT_EQ(a.x_m(), v->x_m());
    EXPECT_EQ(a.z_m(), v->z_m());
    EXPECT_EQ(a.heading_rad(), v->heading_rad());
  }
  EXPECT_GT(a.x_m(), 70.0);
}

TEST(PhysicalVehicle, RefusesBadInputAndChangesNothing) {
  auto t = FlatTerrain();
  EXPECT_FALSE(PhysicalVehicle::Make(PhysType("tank"), *t, 1.0, 100, 0).ok());  // off the edge
  EXPECT_FALSE(PhysicalVehicle::Make(PhysType("tank"), *t, NAN, 100, 0).ok());
  PhysicalVehicleType bad = PhysType("tank");
  bad.mass_kg = -1;
  const auto refused = PhysicalVehicle::Make(bad, *t, 100, 100, 0);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("mass_kg = -1"), std::string::npos)
      << refused.error().message;
  auto bridged = FlatTerrain();
  ASSERT_TRUE(
      bridged->Add({1, 1, 1}, FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 2, 2)).ok());
  const auto inside = PhysicalVehicle::Make(PhysType("tank"), *bridged, 120, 200, 0);
  ASSERT_FALSE(inside.ok());  // under a 2 m span: the roof would be inside the deck
  EXPECT_NE(inside.error().message.find("inside bridge 1:1:1"), std::string::npos)
      << inside.error().message;
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 100, 100, 0).value();
  ASSERT_TRUE(v.Command(5, 0.1).ok());
  const Status s = v.Command(NAN, 0);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("not finite"), std::string::npos);
  EXPECT_EQ(v.commanded_speed_mps(), 5.0);
  EXPECT_FALSE(v.Advance(*t, -0.1).ok());
  EXPECT_FALSE(v.Advance(*t, INFINITY).ok());
  ASSERT_TRUE(v.Command(500, 50).ok());  // clamped, as the kinematic vehicle does
  EXPECT_EQ(v.commanded_speed_mps(), 18.0);
  EXPECT_EQ(v.commanded_rate_rad_s(), 0.7);
}

TEST(PhysicalVehicle, ReachesTopSpeedOnRoadAndStopsAtTheTerrainEdge) {
  auto t = FlatTerrain(400, Material::kAsphalt);
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 30, 100, 0).value();
  Drive(*t, v, 18, 0, 20);
  std::printf("tank on asphalt after 20 s: %.2f m/s at x %.1f m\n", v.speed_mps(), v.x_m());
  EXPECT_NEAR(v.speed_mps(), 18.0, 0.05);
  Drive(*t, v, 18, 0, 20);
  EXPECT_LT(v.x_m(), 400.0 - 3.9);
  EXPECT_GT(v.x_m(), 390.0);
  EXPECT_EQ(v.commanded_speed_mps(), 0.0);
}

TEST(PhysicalVehicle, MudSlowsMoreThanRoad) {
  double distance[2], speed[2];
  const Material soils[2] = {Material::kAsphalt, Material::kMud};
  for (int k = 0; k < 2; ++k) {
    auto t = FlatTerrain(400, soils[k]);
    auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 30, 100, 0).value();
    Drive(*t, v, 18, 0, 15);
    distance[k] = v.x_m() - 30;
    speed[k] = v.speed_mps();
  }
  std::printf(
      "tank, 15 s from rest at full demand: asphalt %.1f m, %.2f m/s; mud %.1f m, %.2f m/s\n",
      distance[0], speed[0], distance[1], speed[1]);
  EXPECT_LT(distance[1], 0.7 * distance[0]);
  EXPECT_LT(speed[1], 0.6 * speed[0]);
  // Mud's top speed is where engine power meets rolling resistance: P / (c m g).
  const PhysicalVehicleType tank = PhysType("tank");
  const double c = tank.grip[static_cast<size_t>(Material::kMud)].rolling_resistance;
  EXPECT_NEAR(speed[1], tank.engine_power_w / (c * tank.mass_kg * kGravityMps2), 0.3);
}

TEST(PhysicalVehicle, ClimbsASlopeTractionAllowsAndNotASteeperOne) {
  for (const double slope : {20.0, 45.0}) {
    auto t = SlopeTerrain(slope);
    auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 80, 200, 0).value();
    const DriveLog log = Drive(*t, v, 8, 0, 20);
    std::printf(
        "tank on a %.0f deg grass slope (static friction 0.80 = %.1f deg): reached x %.1f m, "
        "elevation %.1f m, max pitch %.1f deg\n",
        slope, Deg(std::atan(0.8)), v.x_m(), v.elevation_m(), Deg(log.max_pitch_rad));
    if (slope == 20.0) {
      EXPECT_GT(v.x_m(), 150.0);
    } else {
      EXPECT_LT(v.x_m(), 106.0);
      EXPECT_LT(v.elevation_m(), 16.0);
    }
  }
}

TEST(PhysicalVehicle, SlidesWhereStaticFrictionFailsAndHoldsWhereItDoesNot) {
  // A 32-degree grass slope: beyond a wheeled type's grip (0.55 = 28.8 deg), within a tracked
  // type's (0.80 = 38.7 deg). Both start parked on it, across the slope.
  auto t = SlopeTerrain(32.0);
  for (const char* name : {"tank", "jeep"}) {
    const double x0 = 150.0;
    auto v =
        PhysicalVehicle::MakeAt(PhysType(name), *t, x0, 200, 1.5708,
                                10.0 + 50.0 * std::tan(32.0 * 3.14159265358979323846 / 180.0) + 0.3)
            .value();
    Drive(*t, v, 0, 0, 2);  // settle onto the slope
    const double settled = v.x_m();
    const DriveLog log = Drive(*t, v, 0, 0, 5);
    std::printf(
        "%s parked across a 32 deg grass slope: moved %.3f m downhill in 5 s (sliding %d "
        "ticks), roll %.1f deg\n",
        name, settled - v.x_m(), log.sliding_ticks, Deg(v.roll_rad()));
    if (std::string(name) == "tank") {
      EXPECT_LT(std::abs(settled - v.x_m()), 0.01);
    } else {
      EXPECT_GT(settled - v.x_m(), 1.0);
      EXPECT_GT(log.sliding_ticks, 100);
    }
  }
}

TEST(PhysicalVehicle, FallDamageFollowsTheTypesThresholds) {
  auto t = FlatTerrain();
  struct Case {
    const char* type;
    double height_m;
    Damage expected;
  };
  for (const Case& c :
       {Case{"tank", 0.5, Damage::kNone}, Case{"tank", 3.0, Damage::kImmobilised},
        Case{"tank", 6.0, Damage::kDestroyed}, Case{"jeep", 0.5, Damage::kNone},
        Case{"jeep", 2.0, Damage::kImmobilised}, Case{"jeep", 4.0, Damage::kDestroyed}}) {
    auto v =
        PhysicalVehicle::MakeAt(PhysType(c.type), *t, 100, 100, 0, kGround + c.height_m).value();
    double lowest_drop_tick = 0.0;
    double prev = v.elevation_m();
    const DriveLog log = Drive(*t, v, 0, 0, 3, [&](const PhysicalVehicle& pv) {
      lowest_drop_tick = std::max(lowest_drop_tick, prev - pv.elevation_m());
      prev = pv.elevation_m();
      return false;
    });
    std::printf("%s dropped %.1f m: landed at %.2f m/s (free fall %.2f m/s), %s\n", c.type,
                c.height_m, log.max_landing_mps, std::sqrt(2 * kGravityMps2 * c.height_m),
                std::string(DamageName(v.damage())).c_str());
    EXPECT_NEAR(log.max_landing_mps, std::sqrt(2 * kGravityMps2 * c.height_m), 0.15);
    EXPECT_EQ(v.damage(), c.expected);
    // The fall took time: no tick dropped more than free fall allows by the end of the fall, over
    // the time the tick ran (whole internal steps: 1/30 s runs 3 or 4 of 10 ms).
    const double longest_tick_s = std::ceil(kTick / kPhysicsStepS) * kPhysicsStepS;
    EXPECT_LE(lowest_drop_tick, std::sqrt(2 * kGravityMps2 * c.height_m) * longest_tick_s + 0.01);
  }
  auto wreck = PhysicalVehicle::MakeAt(PhysType("tank"), *t, 200, 100, 0, kGround + 6).value();
  Drive(*t, wreck, 0, 0, 3);
  EXPECT_FALSE(wreck.Command(5, 0).ok());
}

TEST(PhysicalVehicle, AtRestOnFlatGroundStaysAtRest) {
  for (const char* name : {"tank", "truck", "jeep"}) {
    auto t = FlatTerrain(400, Material::kDirt);
    auto v = PhysicalVehicle::Make(PhysType(name), *t, 150, 150, 0.7).value();
    const Eigen::Vector3d x0 = v.position_m();
    Drive(*t, v, 0, 0, 60);
    std::printf("%s at rest 60 s: moved %.3g m, speed %.3g m/s\n", name,
                (v.position_m() - x0).norm(), v.velocity_mps().norm());
    EXPECT_LT((v.position_m() - x0).norm(), 1e-6);
    EXPECT_LT(v.velocity_mps().norm(), 1e-6);
  }
}

// The vehicle keeps what it gathered from the terrain between ticks (docs/vehicles.md "Contacts"):
// a crater made under a parked tank, and its removal, reach it at once.
TEST(PhysicalVehicle, SeesTheTerrainChangeUnderItBetweenTicks) {
  auto t = FlatTerrain();
  auto v = PhysicalVehicle::Make(PhysType("tank"), *t, 150, 150, 0.3).value();
  Drive(*t, v, 0, 0, 2);
  const double parked = v.elevation_m();
  const uint64_t before = t->stamp();
  ASSERT_TRUE(t->Add(FeatureId{1, 1, 1}, FeatureParams::Crater(150, 150, 8.0)).ok());
  EXPECT_NE(t->stamp(), before);
  Drive(*t, v, 0, 0, 4);
  const double in_crater = v.elevation_m();
  ASSERT_TRUE(t->Remove(FeatureId{1, 1, 1}).ok());
  Drive(*t, v, 0, 0, 4);
  std::printf("tank parked at %.3f m; a 16 m crater made under it: %.3f m; removed: %.3f m\n",
              parked, in_crater, v.elevation_m());
  EXPECT_GT(in_crater, parked + 0.3);  // the crater's rim, under its running gear, lifted it
  EXPECT_NEAR(v.elevation_m(), parked, 0.05);  // and is back on the flat ground
}

}  // namespace
}  // namespace dt::test
