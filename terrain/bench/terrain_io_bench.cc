// Benchmarks of random terrain generation, the state digest and terrain file encode/decode.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "terrain/random_terrain.h"
#include "terrain/terrain_digest.h"
#include "terrain/terrain_file.h"

namespace dt {
namespace {

// A random ground of n posts (10 m apart) with up to 256 craters on a 16 x 16 pattern.
std::unique_ptr<Terrain> BenchTerrain(int n) {
  auto t = std::make_unique<Terrain>(MakeRandomTerrain(
      {.posts_x = n, .posts_z = n, .spacing_m = 10.0, .relief_m = 100.0, .seed = 1}));
  const double size_x_m = t->ground().size_x_m(), size_z_m = t->ground().size_z_m();
  uint32_t number = 1;
  for (int a = 0; a < 16; ++a) {
    for (int b = 0; b < 16; ++b) {
      const double x = size_x_m * (a + 0.5) / 16.0, z = size_z_m * (b + 0.5) / 16.0;
      (void)t->Add({1, 1, number++}, FeatureParams::Crater(x, z, 5.0));
    }
  }
  return t;
}

void BM_MakeRandomTerrain(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(MakeRandomTerrain({.posts_x = n, .posts_z = n, .seed = 7}));
  }
  state.SetItemsProcessed(state.iterations() * n * n);
}
BENCHMARK(BM_MakeRandomTerrain)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);

void BM_ComputeDigest(benchmark::State& state) {
  const auto t = BenchTerrain(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(ComputeDigest(*t));
  state.SetLabel(fmt::format("{} features", t->feature_count()));
}
BENCHMARK(BM_ComputeDigest)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);

void BM_EncodeTerrainFile(benchmark::State& state) {
  const auto t = BenchTerrain(static_cast<int>(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state) {
    const auto encoded = EncodeTerrainFile(*t);
    bytes = encoded.size();
    benchmark::DoNotOptimize(encoded.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes));
}
BENCHMARK(BM_EncodeTerrainFile)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);

void BM_DecodeTerrainFile(benchmark::State& state) {
  const auto encoded = EncodeTerrainFile(*BenchTerrain(static_cast<int>(state.range(0))));
  for (auto _ : state) {
    auto loaded = DecodeTerrainFile(encoded, "bench");
    if (!loaded.ok()) state.SkipWithError(loaded.error().message.c_str());
    benchmark::DoNotOptimize(loaded);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * encoded.size()));
}
BENCHMARK(BM_DecodeTerrainFile)->Arg(257)->Arg(1025)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
