// Benchmarks of SettleVehicle: two-point on bare ground, six-point over a crater and over four
// overlapping ones, on a bridge deck.
#include <cstdlib>

#include <benchmark/benchmark.h>

#include "vehicle/vehicle_traversal.h"

namespace dt {
namespace {

constexpr FeatureId kBridgeId{1, 1, 1};

// 600 m of flat ground (2 m spacing) with a crater at (300, 100), four overlapping craters of
// radius 9 m from (450, 150) to (451.5, 150) and a bridge whose span runs x 100..140 at z = 300.
const Terrain& BenchTerrain() {
  static const Terrain* terrain = [] {
    auto* t = new Terrain(HeightGrid(301, 2.0, 10.0f));
    if (!t->Add({1, 1, 2}, FeatureParams::Crater(300, 100, 10)) ||
        !t->Add(kBridgeId, FeatureParams::Bridge(100, 300, 0.0, 10, 30, 40, 30, 6, 8))) {
      std::abort();
    }
    for (uint32_t k = 0; k < 4; ++k) {
      if (!t->Add({1, 1, 3 + k}, FeatureParams::Crater(450 + 0.5 * k, 150, 9.0))) std::abort();
    }
    return t;
  }();
  return *terrain;
}

Vehicle Tank(double x, double z) {
  auto v = Vehicle::Make(TankType(), x, z, 0.0, BenchTerrain().ground().size_x_m(),
                         BenchTerrain().ground().size_z_m());
  if (!v) std::abort();
  return std::move(v).value();
}

void Settle(benchmark::State& state, Vehicle v) {
  const Terrain& t = BenchTerrain();
  for (auto _ : state) {
    auto r = SettleVehicle(t, v);
    benchmark::DoNotOptimize(r);
  }
  state.SetLabel(v.orientation().method == OrientationMethod::kTwoPoint ? "two-point"
                                                                        : "six-point");
}

void BM_SettleBareGround(benchmark::State& state) { Settle(state, Tank(450, 450)); }
BENCHMARK(BM_SettleBareGround);

void BM_SettleOverCrater(benchmark::State& state) { Settle(state, Tank(300, 93)); }
BENCHMARK(BM_SettleOverCrater);

void BM_SettleOverFourCraters(benchmark::State& state) { Settle(state, Tank(451.5, 150)); }
BENCHMARK(BM_SettleOverFourCraters);

void BM_SettleOnBridgeSpan(benchmark::State& state) {
  Vehicle v = Tank(50, 300);
  if (!v.Command(5, 0)) std::abort();
  while (v.x_m() < 120) {
    if (!DriveVehicle(BenchTerrain(), v, 0.1)) std::abort();
  }
  if (!v.on_bridge() || !v.Command(0, 0)) std::abort();
  Settle(state, v);
}
BENCHMARK(BM_SettleOnBridgeSpan);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
