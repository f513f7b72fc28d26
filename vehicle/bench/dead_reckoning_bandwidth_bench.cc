// Bandwidth of shared vehicles under dead reckoning (docs/performance.md "Shared vehicles"): the
// VehicleState PDUs an owner sends per vehicle per second with the exercise's default thresholds
// (1 m, 3 degrees, 5 s heartbeat, RVW), against one PDU per 30 Hz tick, for a vehicle driving
// straight, turning and idling under either model. The counters are the result; the time is the
// owner's bookkeeping per vehicle-tick (model step excluded from nothing: it is included).
#include <algorithm>
#include <cmath>

#include <benchmark/benchmark.h>

#include "terrain/random_terrain.h"
#include "terrain/terrain.h"
#include "vehicle/dead_reckoning.h"
#include "vehicle/dead_reckoning_policy.h"
#include "vehicle/observed_motion.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {
namespace {

constexpr double kTickS = 1.0 / 30.0;
constexpr double kSeconds = 120.0;

enum Motion { kStraight = 0, kTurning = 1, kIdle = 2 };

// Flat ground (relief 0) or rolling ground (relief 20 m over 10 m posts, seed 5), 2 km square.
const Terrain& Ground(bool rolling) {
  static const Terrain* terrains[2] = {nullptr, nullptr};
  if (terrains[rolling] == nullptr) {
    RandomTerrainParams p;
    p.posts_x = p.posts_z = 201;
    p.spacing_m = 10.0;
    p.relief_m = rolling ? 20.0 : 0.0;
    p.seed = 5;
    terrains[rolling] = new Terrain(MakeRandomTerrain(p));
  }
  return *terrains[rolling];
}

void BM_DeadReckoningBandwidth(benchmark::State& state) {
  const auto motion = static_cast<Motion>(state.range(0));
  const auto model = state.range(1) == 0 ? VehicleModel::kLight : VehicleModel::kPhysical;
  const bool rolling = state.range(2) != 0;
  const Terrain& terrain = Ground(rolling);
  const DeadReckoningThresholds thresholds;
  const double speed_mps = motion == kIdle ? 0.0 : 10.0;
  const double rate_rad_s = motion == kTurning ? 0.2 : 0.0;  // a 50 m radius at 10 m/s
  uint64_t sent = 0, ticks = 0;
  double worst_m = 0.0, sum_m = 0.0;
  for (auto _ : state) {
    auto type = BuiltInPhysicalType("tank", ShippedFrictionTable());
    auto v = SimulatedVehicle::Make(type.value(), terrain, motion == kStraight ? 300.0 : 1000.0,
                                    1000.0, 0.0, model);
    SimulatedVehicle vehicle = std::move(v).value();
    MotionEstimator est;
    DeadReckoningOwner owner(thresholds);
    if (!vehicle.Command(speed_mps, rate_rad_s)) state.SkipWithError("command refused");
    for (double t = 0.0; t < kSeconds; t += kTickS) {
      if (!vehicle.Advance(terrain, kTickS)) state.SkipWithError("advance failed");
      const DrPose pose = DrPoseOf(vehicle);
      ObserveVehicle(est, vehicle, t);
      VehicleStateFields s;
      s.location_m = pose.location_m;
      s.heading_rad = pose.heading_rad;
      s.pitch_rad = pose.pitch_rad;
      s.roll_rad = pose.roll_rad;
      s.velocity_mps = est.velocity_mps();
      s.acceleration_mps2 = est.acceleration_mps2();
      s.angular_velocity_body_rad_s = est.angular_velocity_body_rad_s();
      s.algorithm = thresholds.algorithm;
      const double err = owner.PositionErrorM(s, t);
      worst_m = std::max(worst_m, err);
      sum_m += err;
      if (owner.Due(s, t)) owner.Sent(s, t);
      ++ticks;
    }
    sent += owner.sent_count();
  }
  const double runs = static_cast<double>(state.iterations());
  state.counters["pdus_per_vehicle_s"] = static_cast<double>(sent) / (runs * kSeconds);
  state.counters["ratio_to_per_tick"] = static_cast<double>(sent) / static_cast<double>(ticks);
  state.counters["worst_error_m"] = worst_m;
  state.counters["mean_error_m"] = sum_m / static_cast<double>(ticks);
  state.SetItemsProcessed(static_cast<int64_t>(ticks));
}

// motion (0 straight, 1 turning, 2 idle) x model (0 light, 1 physical) x ground (0 flat, 1
// rolling). One iteration is 120 simulated seconds.
BENCHMARK(BM_DeadReckoningBandwidth)
    ->ArgsProduct({{kStraight, kTurning, kIdle}, {0, 1}, {0, 1}})
    ->ArgNames({"motion", "physical", "rolling"})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
