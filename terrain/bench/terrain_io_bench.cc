// Benchmarks of random terrain generation, the state digest and terrain file encode/decode.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

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

// A ground of n x n posts, 1 m apart, beyond what MakeRandomTerrain makes (kMaxPostsPerSide): an
// analytic relief, every post distinct, with 256 craters on a 16 x 16 pattern.
std::unique_ptr<Terrain> LargeTerrain(int n) {
  std::vector<float> posts(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      posts[static_cast<size_t>(j) * n + i] =
          static_cast<float>(20.0 * std::sin(i * 0.003) * std::cos(j * 0.002) + 0.001 * i);
    }
  }
  auto t = std::make_unique<Terrain>(HeightGrid(n, n, 1.0, std::move(posts)));
  uint32_t number = 1;
  for (int a = 0; a < 16; ++a) {
    for (int b = 0; b < 16; ++b) {
      const double x = (n - 1) * (a + 0.5) / 16.0, z = (n - 1) * (b + 0.5) / 16.0;
      (void)t->Add({1, 1, number++}, FeatureParams::Crater(x, z, 5.0));
    }
  }
  return t;
}

// The process's resident and peak resident memory (VmRSS, VmHWM), MB.
std::pair<double, double> ResidentMb() {
  std::ifstream status("/proc/self/status");
  double rss = 0.0, hwm = 0.0;
  for (std::string line; std::getline(status, line);) {
    if (line.starts_with("VmRSS:")) rss = std::stod(line.substr(6)) / 1024.0;
    if (line.starts_with("VmHWM:")) hwm = std::stod(line.substr(6)) / 1024.0;
  }
  return {rss, hwm};
}

// Resets VmHWM to the current resident size (Linux: 5 to clear_refs).
void ResetPeakResident() { std::ofstream("/proc/self/clear_refs") << "5"; }

std::filesystem::path BenchFile(int n) {
  return std::filesystem::temp_directory_path() /
         fmt::format("dt_terrain_io_bench_{}_{}.dtt", ::getpid(), n);
}

// SaveTerrain and LoadTerrain of grounds past 4097 posts a side, on disk (the page cache warm for
// the load). peak_extra_MB: how far the process's peak resident memory rose above where it stood
// before the call, against terrain_MB, what the terrain's grid holds (8 bytes a post): a file read
// or written whole would add its own size.
void BM_SaveTerrain(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto t = LargeTerrain(n);
  const auto path = BenchFile(n);
  double peak_extra_mb = 0.0;
  for (auto _ : state) {
    ResetPeakResident();
    const double before = ResidentMb().first;
    const Status s = SaveTerrain(*t, path);
    if (!s) state.SkipWithError(s.error().message.c_str());
    peak_extra_mb = ResidentMb().second - before;
  }
  state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  state.counters["peak_extra_MB"] = peak_extra_mb;
  std::filesystem::remove(path);
}
BENCHMARK(BM_SaveTerrain)
    ->Arg(1025)
    ->Arg(5001)
    ->Arg(10001)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

void BM_LoadTerrain(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto path = BenchFile(n);
  if (!SaveTerrain(*LargeTerrain(n), path)) state.SkipWithError("SaveTerrain failed");
  double peak_extra_mb = 0.0;
  for (auto _ : state) {
    ResetPeakResident();
    const double before = ResidentMb().first;
    auto loaded = LoadTerrain(path);
    if (!loaded.ok()) state.SkipWithError(loaded.error().message.c_str());
    peak_extra_mb = ResidentMb().second - before;
    benchmark::DoNotOptimize(loaded);
  }
  state.counters["terrain_MB"] = 8.0 * n * n / 1e6;
  state.counters["peak_extra_MB"] = peak_extra_mb;
  std::filesystem::remove(path);
}
BENCHMARK(BM_LoadTerrain)
    ->Arg(1025)
    ->Arg(5001)
    ->Arg(10001)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
