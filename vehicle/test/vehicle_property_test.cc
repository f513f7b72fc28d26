// Property tests of the physical model over seeded random terrains, features and drives: the hull
// never enters the ground or a feature (a drawn bridge solid) by more than 0.1 m, no tick drops
// the vehicle further than free fall allows, a destroyed vehicle comes to rest on a support, and a
// vehicle at rest on flat ground stays at rest. DT_VEHICLE_SEEDS sets the
// number of seeds (default 4) and DT_VEHICLE_FIRST_SEED the first (default 1), so one seed runs
// alone; DT_VEHICLE_TRACE=1 prints each tick that drops beyond free fall.
#include <cstdlib>
#include <random>

#include "terrain/random_terrain.h"
#include "vehicle/contact_surface.h"
#include "vehicle/hull_collision.h"
#include "vehicle/test/vehicle_fixtures.h"

namespace dt::test {
namespace {

int FirstSeed() {
  const char* s = std::getenv("DT_VEHICLE_FIRST_SEED");
  return s ? std::max(1, std::atoi(s)) : 1;
}
// The last seed run.
int Seeds() {
  const char* s = std::getenv("DT_VEHICLE_SEEDS");
  return s ? std::max(1, std::atoi(s)) : 4;
}

constexpr const char* kTypes[] = {"tank", "truck", "jeep"};

struct World {
  std::unique_ptr<Terrain> terrain;
  int features = 0;
};

// 200 m of value-noise ground (8 m relief, 2 m posts) with craters, berms and, on odd seeds, an
// intact or destroyed bridge, all at random.
World RandomWorld(uint64_t seed) {
  RandomTerrainParams p;
  p.posts_x = p.posts_z = 101;
  p.spacing_m = 2.0;
  p.relief_m = 8.0;
  p.seed = seed;
  World w{std::make_unique<Terrain>(MakeRandomTerrain(p))};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(40, 160), unit(0, 1);
  uint32_t number = 1;
  for (int k = 0; k < 6; ++k) {
    w.features +=
        w.terrain
            ->Add({1, 1, number++}, FeatureParams::Crater(pos(rng), pos(rng), 3 + 7 * unit(rng)))
            .ok();
  }
  for (int k = 0; k < 4; ++k) {
    w.features +=
        w.terrain
            ->Add({1, 1, number++},
                  FeatureParams::Berm(pos(rng), pos(rng), 6.28 * unit(rng), 10 + 20 * unit(rng),
                                      4 + 4 * unit(rng), 0.5 + unit(rng)))
            .ok();
  }
  if (seed % 2 == 1) {
    FeatureParams b =
        FeatureParams::Bridge(80 + 20 * unit(rng), 80 + 40 * unit(rng), 6.28 * unit(rng), 10, 20,
                              20, 20, 2 + 4 * unit(rng), 2 + 4 * unit(rng));
    if (unit(rng) < 0.5) b.status = BridgeStatus::kDestroyed;
    w.features += w.terrain->Add({1, 1, number++}, b).ok();
  }
  return w;
}

struct Worst {
  double ground_m = 0.0, solid_m = 0.0, drop_excess_m = -INFINITY;
  std::string damage;
  // A destroyed vehicle, left alone after the drive: at rest (asleep) and how far its lowest
  // point is from what lies under it (SupportGap).
  bool wreck = false, wreck_at_rest = false;
  double wreck_gap_m = 0.0;
};

// Drives a random vehicle with random demands changed every 2 s for `seconds`, checking each tick.
Worst RandomDrive(const Terrain& t, uint64_t seed, double seconds) {
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> unit(0, 1);
  const PhysicalVehicleType type = PhysType(kTypes[seed % 3]);
  // Random places until one is clear of bridge solids (a hull inside one is refused).
  Result<PhysicalVehicle> made = Error{"not placed"};
  while (!made) {
    made =
        PhysicalVehicle::Make(type, t, 60 + 80 * unit(rng), 60 + 80 * unit(rng), 6.28 * unit(rng));
  }
  PhysicalVehicle v = std::move(made).value();
  Worst worst;
  double y_prev = v.position_m().y(), vy_prev = v.velocity_mps().y();
  for (int i = 0; i < static_cast<int>(seconds / kTick); ++i) {
    if (i % 60 == 0 && v.mobile()) {
      const double speed = -type.base.max_reverse_speed_mps +
                           unit(rng) * (type.base.max_speed_mps + type.base.max_reverse_speed_mps);
      EXPECT_TRUE(v.Command(speed, (2 * unit(rng) - 1) * type.base.max_turn_rate_rad_s).ok());
    }
    const bool was_wreck = !v.alive();
    const PhysicalReport r = v.Advance(t, kTick).value();
    // Depth below the ground and earthworks, along the surface's normal (a point 0.1 m into a
    // 45-degree face is 0.14 m below it): the hull's bottom, and a wreck's whole box from the tick
    // after the one it was destroyed in (the box's running gear, on its travel up to then, is on
    // the ground's side of it).
    for (const Eigen::Vector3d& p : was_wreck ? BoxPoints(v, 0.25) : v.HullBottomPoints(0.25)) {
      const SurfaceSample s = SampleSurface(t, {}, p.x(), p.z(), p.y());
      const double depth = (t.ElevationAt(p.x(), p.z()) - p.y()) * s.normal.y();
      if (depth > 0.1 && std::getenv("DT_VEHICLE_TRACE")) {
        std::printf(
            "  tick %d point (%.2f, %.2f, %.2f) %.3f m in, normal y %.2f; %s pitch %.1f "
            "roll %.1f\n",
            i, p.x(), p.y(), p.z(), depth, s.normal.y(),
            std::string(DamageName(v.damage())).c_str(), Deg(v.pitch_rad()), Deg(v.roll_rad()));
      }
      worst.ground_m = std::max(worst.ground_m, depth);
    }
    const std::vector<Solid> solids =
        SolidsNear(t, Rect{v.x_m(), v.z_m(), v.x_m(), v.z_m()}.Expanded(15));
    // No pose inside a drawn solid: the renderer draws a bridge as these solids
    // (render/bridge_mesh.h), so the hull's box (a wreck's from the gear's bottom) is checked.
    const std::vector<Eigen::Vector3d> box = BoxPoints(v, 0.5, !was_wreck);
    const HullPenetration in = DeepestPenetration(box, solids, INFINITY);
    if (in.depth_m > 0.1 && std::getenv("DT_VEHICLE_TRACE")) {
      std::printf(
          "  tick %d solid: point (%.2f, %.2f, %.2f) %.3f m in, normal (%.2f, %.2f, %.2f); "
          "%s pitch %.1f roll %.1f\n",
          i, in.point_m.x(), in.point_m.y(), in.point_m.z(), in.depth_m, in.normal.x(),
          in.normal.y(), in.normal.z(), std::string(DamageName(v.damage())).c_str(),
          Deg(v.pitch_rad()), Deg(v.roll_rad()));
    }
    worst.solid_m = std::max(worst.solid_m, in.depth_m);
    // Free fall from the last tick's vertical speed bounds how far the centre of mass can drop.
    const double y = v.position_m().y();
    // A tick runs whole internal steps (3 or 4 of 10 ms), and semi-implicit Euler falls
    // g T (T + h) / 2 in T = n h from rest.
    const double T = r.steps * kPhysicsStepS;
    const double allowed =
        std::max(0.0, -vy_prev) * T + 0.5 * kGravityMps2 * T * (T + kPhysicsStepS);
    if ((y_prev - y) - allowed > 1e-3 && std::getenv("DT_VEHICLE_TRACE")) {
      std::printf("  tick %d drop %.4f allowed %.4f blocked %d at (%.1f, %.1f) bridge %u\n", i,
                  y_prev - y, allowed, r.blocked, v.x_m(), v.z_m(), v.bridge().number);
    }
    worst.drop_excess_m = std::max(worst.drop_excess_m, (y_prev - y) - allowed);
    y_prev = y;
    vy_prev = v.velocity_mps().y();
  }
  worst.damage = std::string(DamageName(v.damage()));
  if (!v.alive()) {
    // A wreck is a body under gravity: left alone, it comes to rest on a support.
    worst.wreck = true;
    for (int i = 0; i < 30 * 30 && !v.asleep(); ++i) {
      v.Advance(t, kTick).value();
      if (i % 30 == 0 && std::getenv("DT_VEHICLE_TRACE")) {
        std::printf(
            "  wreck %d s: (%.3f, %.3f, %.3f) speed %.3f m/s, turning %.3f rad/s, pitch "
            "%.1f roll %.1f\n",
            i / 30, v.x_m(), v.position_m().y(), v.z_m(), v.velocity_mps().norm(),
            v.angular_velocity_rad_s().norm(), Deg(v.pitch_rad()), Deg(v.roll_rad()));
      }
    }
    worst.wreck_at_rest = v.asleep();
    worst.wreck_gap_m = SupportGap(t, v);
  }
  return worst;
}

void CheckSeed(int s) {
  const World w = RandomWorld(static_cast<uint64_t>(s));
  const Worst worst = RandomDrive(*w.terrain, static_cast<uint64_t>(s), 20.0);
  std::printf(
      "seed %d (%s, %d features): deepest hull penetration ground %.3f m, bridge solids "
      "%.3f m; largest drop beyond free fall %.4f m; damage %s\n",
      s, kTypes[s % 3], w.features, worst.ground_m, worst.solid_m, worst.drop_excess_m,
      worst.damage.c_str());
  EXPECT_LE(worst.ground_m, 0.1) << "seed " << s;
  EXPECT_LE(worst.solid_m, 0.1) << "seed " << s;
  EXPECT_LE(worst.drop_excess_m, 1e-3) << "seed " << s;
  if (worst.wreck) {
    std::printf("  wreck: at rest %d, support gap %.3f m\n", worst.wreck_at_rest,
                worst.wreck_gap_m);
    EXPECT_TRUE(worst.wreck_at_rest) << "seed " << s;
    EXPECT_LE(std::abs(worst.wreck_gap_m), 0.1) << "seed " << s;
  }
}

TEST(VehicleProperty, HullStaysOutOfGroundAndFeaturesAndNoTickOutfallsFreeFall) {
  for (int s = FirstSeed(); s <= Seeds(); ++s) CheckSeed(s);
}

// Seeds that once failed, run whatever DT_VEHICLE_SEEDS says.
// 239, 275, 281: a roof under a ramp's sloping underside was pushed straight down step after
// step, its velocity into the face taken as vertical only, while driving on under the slope
// kept pushing it in: the body sank faster than it could fall (2-8 mm a tick).
TEST(VehicleProperty, RoofUnderASlopingUndersideIsNotDrivenDownFasterThanItFalls) {
  for (const int s : {239, 275, 281}) CheckSeed(s);
}
// 288: a tank's belly 0.101 m into an earthwork; 295: a tick 2 mm past free fall near a bridge.
// Both pass since the 10 ms step and the belly's queries of the gathered earthworks.
// 23, 115, 641: failed under a 20 ms step with 10 ms substeps near features (a jeep pushed 5 mm
// past free fall against a bridge solid; trucks tipping over 0.1002 m into the ground), passing
// at 10 ms throughout (docs/vehicles.md "Time step").
TEST(VehicleProperty, EarlierFailuresNearEarthworksAndBridges) {
  for (const int s : {288, 295, 23, 115, 641}) CheckSeed(s);
}
// 267, 833: a roof corner driven on into a ramp's sloping underside at 1-2 m/s, the slope turning
// the forward speed into a downward push (1-3 mm a tick past free fall). The wedge now stops the
// vehicle: it goes back level out from under the slope.
TEST(VehicleProperty, DrivingIntoAWedgeUnderARampStopsRatherThanSqueezesDown) {
  for (const int s : {267, 833}) CheckSeed(s);
}

TEST(VehicleProperty, AtRestOnFlatGroundStaysAtRest) {
  constexpr Material kSoils[] = {Material::kGrass, Material::kMud, Material::kConcrete,
                                 Material::kSand};
  for (int s = FirstSeed(); s <= Seeds(); ++s) {
    std::mt19937_64 rng(static_cast<uint64_t>(s));
    std::uniform_real_distribution<double> unit(0, 1);
    const float elevation = static_cast<float>(100 * unit(rng));
    Terrain t(HeightGrid(101, 2.0, elevation, kSoils[s % 4]));
    auto v = PhysicalVehicle::Make(PhysType(kTypes[s % 3]), t, 50 + 100 * unit(rng),
                                   50 + 100 * unit(rng), 6.28 * unit(rng) - 3.14)
                 .value();
    const Eigen::Vector3d x0 = v.position_m();
    Drive(t, v, 0, 0, 30);
    std::printf("seed %d (%s on %s at %.1f m): moved %.3g m in 30 s, speed %.3g m/s\n", s,
                kTypes[s % 3], std::string(MaterialName(kSoils[s % 4])).c_str(), elevation,
                (v.position_m() - x0).norm(), v.velocity_mps().norm());
    EXPECT_LT((v.position_m() - x0).norm(), 1e-6) << "seed " << s;
    EXPECT_LT(v.velocity_mps().norm(), 1e-6) << "seed " << s;
  }
}

}  // namespace
}  // namespace dt::test
