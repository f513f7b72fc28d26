// Benchmark: rendering a 2048 x 2048 map of a 10 km x 10 km terrain with 10^4 features.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "render/renderer.h"
#include "terrain/random_terrain.h"

namespace dt {
namespace {

// 1001 x 1001 posts at 10 m: 10 km a side, 2 million ground triangles.
// 10^4 features: 7000 craters (radius 5..40 m), 2900 berms (20..200 m long), 100 bridges on a
// lattice so they never overlap. Positions come from a fixed seed.
const Terrain& BigTerrain() {
  static const Terrain terrain = [] {
    RandomTerrainParams p;
    p.posts_x = p.posts_z = 1001;
    p.spacing_m = 10.0;
    p.relief_m = 200.0;
    p.seed = 42;
    Terrain t(MakeRandomTerrain(p));
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> pos(300.0, 9700.0), unit(0.0, 1.0);
    uint32_t n = 0;
    while (t.feature_count() < 7000) {
      (void)t.Add({1, 1, ++n}, FeatureParams::Crater(pos(rng), pos(rng), 5.0 + 35.0 * unit(rng)));
    }
    while (t.feature_count() < 9900) {
      (void)t.Add({1, 2, ++n},
                  FeatureParams::Berm(pos(rng), pos(rng), 2.0 * std::numbers::pi * unit(rng),
                                      20.0 + 180.0 * unit(rng), 4.0 + 8.0 * unit(rng),
                                      1.0 + 3.0 * unit(rng)));
    }
    for (int k = 0; k < 100; ++k) {
      const double x = 400.0 + (k % 10) * 950.0, z = 450.0 + (k / 10) * 950.0;
      FeatureParams b = FeatureParams::Bridge(x, z, 0.0, 10.0, 40.0, 120.0, 40.0, 8.0, 8.0);
      if (k % 3 == 0) b.status = BridgeStatus::kDestroyed;
      (void)t.Add({1, 3, ++n}, b);
    }
    return t;
  }();
  return terrain;
}

void BM_RenderMap2048(benchmark::State& state) {
  const Terrain& t = BigTerrain();
  Renderer renderer;
  const Camera camera = Camera::MapOf({0.0, 0.0, 10000.0, 10000.0}, 2048);
  for (auto _ : state) {
    Image im = renderer.Render(t, {}, camera);
    benchmark::DoNotOptimize(im.bytes().data());
  }
  state.counters["features"] = static_cast<double>(t.feature_count());
}
BENCHMARK(BM_RenderMap2048)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_RenderPerspective1280x720(benchmark::State& state) {
  const Terrain& t = BigTerrain();
  Renderer renderer;
  const Camera camera = Camera::Perspective({-1000.0, 1500.0, -1000.0}, {5000.0, 0.0, 5000.0},
                                            std::numbers::pi / 3, 1280, 720, 10.0, 30000.0);
  for (auto _ : state) {
    Image im = renderer.Render(t, {}, camera);
    benchmark::DoNotOptimize(im.bytes().data());
  }
}
BENCHMARK(BM_RenderPerspective1280x720)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
