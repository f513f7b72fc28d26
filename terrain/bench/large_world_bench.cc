// Benchmarks of a large world: an elevation query on a 10001^2-post ground mapped from a ground
// cache file against the same on a 1001^2 grid with craters at the same density, and opening a
// warm ground cache file (its checks included) per 10^6 posts (docs/real-ground.md "Large worlds").
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "terrain/ground_cache.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

constexpr double kSpacingM = 1.0;
constexpr double kCratersPerKm2 = 1000.0;
constexpr size_t kPoints = 1 << 16;

std::filesystem::path CacheDir() {
  return std::filesystem::temp_directory_path() / ("large_world_bench." + std::to_string(getuid()));
}

// An analytic surface: ridges and a slope.
HeightGrid Surface(int posts) {
  std::vector<float> y(static_cast<size_t>(posts) * posts);
  for (int j = 0; j < posts; ++j) {
    for (int i = 0; i < posts; ++i) {
      const double x = i * kSpacingM, z = j * kSpacingM;
      y[static_cast<size_t>(j) * posts + i] = static_cast<float>(
          200.0 + 0.01 * x + 0.005 * z + 40.0 * std::sin(x / 90.0) * std::cos(z / 70.0));
    }
  }
  return HeightGrid(posts, posts, kSpacingM, std::move(y));
}

struct World {
  std::unique_ptr<Terrain> terrain;
  std::vector<std::pair<double, double>> uniform;  // anywhere on the world
  std::vector<std::pair<double, double>> local;    // a vehicle's 200 m neighbourhood, moving
  // The same, the vehicle covering the same distance (kSteadyPathM) in every world: `local`'s
  // vehicle crosses the world's middle third, ten times farther on the 10001^2 world than on the
  // 1001^2 one in the same number of queries, so its neighbourhood is renewed ten times as often.
  std::vector<std::pair<double, double>> steady;
};

// The distance the `steady` vehicle covers over kPoints queries: the 1001^2 world's middle third.
constexpr double kSteadyPathM = 1000.0 / 3;

// posts x posts at 1 m, mapped from a ground cache file when `mapped`, with craters at
// kCratersPerKm2.
World& Get(int posts, bool mapped) {
  static std::map<std::pair<int, bool>, std::unique_ptr<World>> worlds;
  auto& slot = worlds[{posts, mapped}];
  if (slot) return *slot;
  slot = std::make_unique<World>();
  World& w = *slot;
  HeightGrid ground =
      mapped ? OpenGroundCache(CacheDir(), "large_world_bench " + std::to_string(posts),
                               [&] { return Surface(posts); })
                   .grid
             : Surface(posts);
  w.terrain = std::make_unique<Terrain>(std::move(ground));
  const double size_m = w.terrain->ground().size_x_m();
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pos(20.0, size_m - 20.0);
  std::uniform_real_distribution<double> radius(2.0, 10.0);
  const auto craters = static_cast<int64_t>(kCratersPerKm2 * size_m * size_m / 1e6);
  for (int64_t k = 0; k < craters; ++k) {
    const FeatureId id{1, 1, static_cast<uint32_t>(k + 1)};
    if (!w.terrain->Add(id, FeatureParams::Crater(pos(rng), pos(rng), radius(rng))).ok()) {
      std::abort();
    }
  }
  std::uniform_real_distribution<double> unit(-100.0, 100.0);
  for (size_t k = 0; k < kPoints; ++k) {
    w.uniform.emplace_back(pos(rng), pos(rng));
    // The vehicle crosses the world's middle third; each point within 100 m of it.
    const double t = static_cast<double>(k) / kPoints;
    const double dx = unit(rng), dz = unit(rng);
    w.local.emplace_back(size_m * (1.0 / 3 + t / 3) + dx, size_m / 2 + dz);
    w.steady.emplace_back(size_m / 2 + kSteadyPathM * (t - 0.5) + dx, size_m / 2 + dz);
  }
  return w;
}

// `ground_only`: the bare ground's elevation alone (no feature tables), which tells the posts'
// share of a query from the features'.
enum class Where { kUniform, kLocal, kSteady };

void Query(benchmark::State& state, Where where, bool ground_only = false) {
  const World& w = Get(static_cast<int>(state.range(0)), state.range(1) != 0);
  const auto& points =
      where == Where::kLocal ? w.local : (where == Where::kSteady ? w.steady : w.uniform);
  size_t k = 0;
  double sum = 0.0;
  for (auto _ : state) {
    const auto& [x, z] = points[k++ & (kPoints - 1)];
    sum += ground_only ? w.terrain->GroundElevationAt(x, z) : w.terrain->ElevationAt(x, z);
  }
  benchmark::DoNotOptimize(sum);
  state.counters["features"] = static_cast<double>(w.terrain->feature_count());
}

void BM_QueryUniform(benchmark::State& state) { Query(state, Where::kUniform); }
void BM_QueryLocal(benchmark::State& state) { Query(state, Where::kLocal); }
void BM_QuerySteady(benchmark::State& state) { Query(state, Where::kSteady); }
// {posts a side, mapped}: the 1001^2 grid in memory against the 10001^2 mapped world.
BENCHMARK(BM_QueryUniform)->Args({1001, 0})->Args({10001, 1});
BENCHMARK(BM_QueryLocal)->Args({1001, 0})->Args({10001, 1});
BENCHMARK(BM_QuerySteady)->Args({1001, 0})->Args({10001, 1});
void BM_GroundQueryUniform(benchmark::State& state) { Query(state, Where::kUniform, true); }
void BM_GroundQueryLocal(benchmark::State& state) { Query(state, Where::kLocal, true); }
BENCHMARK(BM_GroundQueryUniform)->Args({1001, 0})->Args({10001, 1});
BENCHMARK(BM_GroundQueryLocal)->Args({1001, 0})->Args({10001, 1});

// The whole terrain's digest read afresh (the ground's 10^8 posts, then every feature), as a
// server printed on its way out, against the remembered digest after one feature changed
// (TerrainDigester: the ground's hash state kept, the features hashed again).
void BM_DigestWhole(benchmark::State& state) {
  World& w = Get(static_cast<int>(state.range(0)), state.range(1) != 0);
  for (auto _ : state) benchmark::DoNotOptimize(ComputeDigest(*w.terrain));
}
void BM_DigestAfterOneFeature(benchmark::State& state) {
  World& w = Get(static_cast<int>(state.range(0)), state.range(1) != 0);
  TerrainDigester digester;
  (void)digester.Of(*w.terrain);
  const FeatureId id{9, 9, 1};
  const double middle_m = w.terrain->ground().size_x_m() / 2;
  for (auto _ : state) {
    state.PauseTiming();
    if (!w.terrain->Add(id, FeatureParams::Crater(middle_m, middle_m, 3.0)).ok()) std::abort();
    state.ResumeTiming();
    benchmark::DoNotOptimize(digester.Of(*w.terrain));
    state.PauseTiming();
    if (!w.terrain->Remove(id).ok()) std::abort();
    state.ResumeTiming();
  }
}
BENCHMARK(BM_DigestWhole)->Args({10001, 1})->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DigestAfterOneFeature)->Args({10001, 1})->Unit(benchmark::kMillisecond)->Iterations(5);

// Opening the warm cache file: reading the header, hashing every byte after it (from the page
// cache) and mapping it; the time per 10^6 posts is the time over the counter posts_1e6.
void BM_OpenWarmCache(benchmark::State& state) {
  const int posts = static_cast<int>(state.range(0));
  const std::string key = "large_world_bench " + std::to_string(posts);
  (void)OpenGroundCache(CacheDir(), key, [&] { return Surface(posts); });
  for (auto _ : state) {
    GroundCacheOpened o = OpenGroundCache(CacheDir(), key, [&] { return Surface(posts); });
    if (o.built) std::abort();
    benchmark::DoNotOptimize(o.grid.post(0, 0));
  }
  state.counters["posts_1e6"] = static_cast<double>(posts) * posts / 1e6;
}
BENCHMARK(BM_OpenWarmCache)->Arg(5001)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt
BENCHMARK_MAIN();
