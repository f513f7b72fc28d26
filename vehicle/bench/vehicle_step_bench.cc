// Benchmarks of the vehicle models on a terrain holding 10^6 craters: one 30 Hz tick per vehicle
// under the physical model (its internal steps included) and under the light model, a node's
// autonomous group of 10 000 wandering vehicles ticked whole, and one contact-surface query
// against one elevation query at the same points.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "terrain/crater.h"
#include "terrain/friction_table.h"
#include "terrain/terrain.h"
#include "vehicle/contact_surface.h"
#include "vehicle/light_vehicle.h"
#include "vehicle/physical_vehicle.h"
#include "vehicle/simulated_vehicle.h"
#include "vehicle/wander.h"

namespace dt {
namespace {

constexpr double kCratersPerKm2 = 128.0;  // as terrain_query_bench
constexpr double kSpacingM = 125.0;
constexpr int kVehicles = 256;
constexpr double kTickS = 1.0 / 30.0;

struct Field {
  std::unique_ptr<Terrain> terrain;
  double size_m = 0.0;
  std::vector<std::pair<double, double>> bare_points, crater_points;
};

const Field& TheField(int64_t count) {
  static std::unique_ptr<Field> field;
  if (field) return *field;
  field = std::make_unique<Field>();
  Field& f = *field;
  const double area_km2 = static_cast<double>(count) / kCratersPerKm2;
  const int squares = static_cast<int>(std::ceil(std::sqrt(area_km2) * 1000.0 / kSpacingM));
  f.terrain = std::make_unique<Terrain>(HeightGrid(squares + 1, kSpacingM, 50.0f));
  f.size_m = f.terrain->ground().size_x_m();  // the field is square
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pos(20.0, f.size_m - 20.0), radius(2.0, 10.0);
  for (int64_t k = 0; k < count; ++k) {
    const FeatureId id{1, 1, static_cast<uint32_t>(k + 1)};
    if (!f.terrain->Add(id, FeatureParams::Crater(pos(rng), pos(rng), radius(rng))).ok())
      std::abort();
  }
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  while (f.bare_points.size() < 4096 || f.crater_points.size() < 4096) {
    const double x = pos(rng), z = pos(rng);
    const auto near = f.terrain->FeaturesNear(x, z);
    if (near.empty() && f.bare_points.size() < 4096) f.bare_points.emplace_back(x, z);
    if (near.size() == 1 && f.crater_points.size() < 4096) {
      const auto* c = static_cast<const Crater*>(near[0]);
      const double px = c->x_m() + 0.5 * c->radius_m() * unit(rng);
      const double pz = c->z_m() + 0.5 * c->radius_m() * unit(rng);
      if (f.terrain->FeaturesNear(px, pz).size() == 1) f.crater_points.emplace_back(px, pz);
    }
  }
  return f;
}

const FrictionTable& Friction() {
  static const FrictionTable table =
      FrictionTable::LoadFile(std::string(DT_SOURCE_DIR) + "/configs/friction.toml");
  return table;
}

constexpr const char* kTypes[] = {"tank", "truck", "jeep"};

// kVehicles vehicles at random places, each driving at a random speed and turn rate.
struct Fleet {
  std::vector<PhysicalVehicle> physical;
  std::vector<LightVehicle> light;
};

Fleet MakeFleet(const Field& f) {
  Fleet fleet;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(1000.0, f.size_m - 1000.0), unit(0.0, 1.0);
  for (int k = 0; k < kVehicles; ++k) {
    const PhysicalVehicleType type = BuiltInPhysicalType(kTypes[k % 3], Friction()).value();
    const double x = pos(rng), z = pos(rng), heading = 6.28 * unit(rng);
    const double speed = 3.0 + 10.0 * unit(rng), rate = 0.1 * (unit(rng) - 0.5);
    PhysicalVehicle p = PhysicalVehicle::Make(type, *f.terrain, x, z, heading).value();
    if (!p.Command(speed, rate)) std::abort();
    fleet.physical.push_back(std::move(p));
    LightVehicle l = LightVehicle::Make(type.base, *f.terrain, x, z, heading).value();
    if (!l.Command(speed, rate)) std::abort();
    fleet.light.push_back(std::move(l));
  }
  return fleet;
}

void PerVehicleTick(benchmark::State& state, int64_t ticks) {
  state.counters["ns_per_vehicle_tick"] =
      benchmark::Counter(static_cast<double>(ticks) * kVehicles * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Each iteration is one 30 Hz tick of the whole fleet, from `state.range(1)` ticks after the fleet
// set off, for kMeasuredTicks ticks: a fixed window, so the figure does not depend on how many
// iterations the library chooses. Early, the fleet is driving; a minute on, some of it has run
// into craters and stuck, or landed hard and rests immobilised.
constexpr int kMeasuredTicks = 300;

void BM_PhysicalTick(benchmark::State& state) {
  const Field& f = TheField(state.range(0));
  Fleet fleet = MakeFleet(f);
  for (int64_t i = 0; i < state.range(1); ++i) {
    for (PhysicalVehicle& v : fleet.physical) (void)v.Advance(*f.terrain, kTickS);
  }
  int64_t ticks = 0;
  for (auto _ : state) {
    for (PhysicalVehicle& v : fleet.physical) {
      auto r = v.Advance(*f.terrain, kTickS);
      benchmark::DoNotOptimize(r);
    }
    ++ticks;
  }
  int asleep = 0;
  for (const PhysicalVehicle& v : fleet.physical) asleep += v.asleep() ? 1 : 0;
  state.counters["asleep_at_end"] = asleep;
  PerVehicleTick(state, ticks);
}

void BM_LightTick(benchmark::State& state) {
  const Field& f = TheField(state.range(0));
  Fleet fleet = MakeFleet(f);
  for (int64_t i = 0; i < state.range(1); ++i) {
    for (LightVehicle& v : fleet.light) (void)v.Advance(*f.terrain, kTickS);
  }
  int64_t ticks = 0;
  for (auto _ : state) {
    for (LightVehicle& v : fleet.light) {
      auto r = v.Advance(*f.terrain, kTickS);
      benchmark::DoNotOptimize(r);
    }
    ++ticks;
  }
  PerVehicleTick(state, ticks);
}

// CPU time of the calling thread: one core's work, whatever else the machine runs.
double ThreadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// A node's group (docs/vehicles.md "Autonomous groups"): `state.range(2)` vehicles of the model
// `state.range(3)` names (0 physical, 1 light), trucks, tanks and jeeps in turn, each placed and
// steered by its Wanderer over the whole field as NodeApp does; an iteration is one 30 Hz tick of
// the whole group (wander, command, advance). Counters: each tick's CPU time, p50 and p99 (ms).
void BM_GroupTick(benchmark::State& state) {
  const Field& f = TheField(state.range(0));
  const auto model = static_cast<VehicleModel>(state.range(3));
  const WanderArea area{0.0, f.size_m, 0.0, f.size_m};
  std::vector<SimulatedVehicle> group;
  std::vector<Wanderer> wanderers;
  for (int64_t i = 0; i < state.range(2); ++i) {
    const PhysicalVehicleType type = BuiltInPhysicalType(kTypes[i % 3], Friction()).value();
    const uint64_t seed = WanderSeed(5, static_cast<uint64_t>(i));
    Wanderer w(type.base, area, f.size_m, f.size_m, seed);
    WanderRandom place(seed + 1);
    for (int attempt = 0;; ++attempt) {
      const WanderStart s = DrawWanderStart(w.clear_area(), place);
      Result<SimulatedVehicle> v =
          SimulatedVehicle::Make(type, *f.terrain, s.x_m, s.z_m, s.heading_rad, model);
      if (v) {
        group.push_back(std::move(v).value());
        break;
      }
      if (attempt == 100) std::abort();
    }
    wanderers.push_back(std::move(w));
  }
  auto tick = [&] {
    for (size_t i = 0; i < group.size(); ++i) {
      SimulatedVehicle& v = group[i];
      if (v.alive() && v.damage() == Damage::kNone) {
        const WanderCommand c = wanderers[i].Next(v.pose(), kTickS, *f.terrain);
        if (c.speed_mps != v.commanded_speed_mps() ||
            c.heading_rate_rad_s != v.commanded_rate_rad_s()) {
          (void)v.Command(c.speed_mps, c.heading_rate_rad_s);
        }
      }
      auto r = v.Advance(*f.terrain, kTickS);
      benchmark::DoNotOptimize(r);
    }
  };
  for (int64_t i = 0; i < state.range(1); ++i) tick();
  std::vector<double> tick_ms;
  for (auto _ : state) {
    const double t0 = ThreadCpuS();
    tick();
    tick_ms.push_back((ThreadCpuS() - t0) * 1e3);
  }
  std::sort(tick_ms.begin(), tick_ms.end());
  auto at = [&](double q) {
    return tick_ms[std::min(tick_ms.size() - 1,
                            static_cast<size_t>(q * static_cast<double>(tick_ms.size())))];
  };
  state.counters["p50_ms"] = at(0.5);
  state.counters["p99_ms"] = at(0.99);
  int wrecks = 0, stopped = 0;
  for (const SimulatedVehicle& v : group) {
    wrecks += v.alive() ? 0 : 1;
    stopped += v.damage() == Damage::kNone ? 0 : 1;
  }
  state.counters["destroyed_at_end"] = wrecks;
  state.counters["damaged_at_end"] = stopped;
}

void ContactQuery(benchmark::State& state, bool crater) {
  const Field& f = TheField(state.range(0));
  const auto& points = crater ? f.crater_points : f.bare_points;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [x, z] = points[k++ & 4095];
    benchmark::DoNotOptimize(SampleSurface(*f.terrain, {}, x, z, 1e9));
  }
}
void ElevationQuery(benchmark::State& state, bool crater) {
  const Field& f = TheField(state.range(0));
  const auto& points = crater ? f.crater_points : f.bare_points;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [x, z] = points[k++ & 4095];
    benchmark::DoNotOptimize(f.terrain->ElevationAt(x, z));
  }
}

void BM_ContactQueryBare(benchmark::State& s) { ContactQuery(s, false); }
void BM_ElevationQueryBare(benchmark::State& s) { ElevationQuery(s, false); }
void BM_ContactQueryCrater(benchmark::State& s) { ContactQuery(s, true); }
void BM_ElevationQueryCrater(benchmark::State& s) { ElevationQuery(s, true); }

// Arguments: features, ticks driven before the window (1 s: settled and up to speed; 60 s).
BENCHMARK(BM_PhysicalTick)
    ->Args({1'000'000, 30})
    ->Args({1'000'000, 1800})
    ->Iterations(kMeasuredTicks)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LightTick)
    ->Args({1'000'000, 30})
    ->Args({1'000'000, 1800})
    ->Iterations(kMeasuredTicks)
    ->Unit(benchmark::kMicrosecond);
// Arguments: features, ticks before the window (1 s, 60 s), vehicles, model (0 physical, 1 light).
// 60 ticks (2 s) a window: each is a whole group's tick, 10 000 vehicles.
BENCHMARK(BM_GroupTick)
    ->Args({1'000'000, 30, 10'000, 0})
    ->Args({1'000'000, 1800, 10'000, 0})
    ->Args({1'000'000, 30, 10'000, 1})
    ->Iterations(60)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ElevationQueryBare)->Arg(1'000'000);
BENCHMARK(BM_ContactQueryBare)->Arg(1'000'000);
BENCHMARK(BM_ElevationQueryCrater)->Arg(1'000'000);
BENCHMARK(BM_ContactQueryCrater)->Arg(1'000'000);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
