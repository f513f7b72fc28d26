// Load time of an exercise's ground from a GeoTIFF (UTM, 10 m pixels), per 10^6 posts: the
// file's header and georeference, the window read and every post interpolated.
#include <cmath>
#include <filesystem>

#include <benchmark/benchmark.h>

#include "geo/elevation_loader.h"
#include "geo/test/test_rasters.h"

namespace {

std::filesystem::path Raster(int side) {
  static const std::filesystem::path dir = dt::testing::FreshTestDir("geo_load_bench");
  const auto path = dir / ("utm_" + std::to_string(side) + ".tif");
  if (!std::filesystem::exists(path)) {
    dt::testing::TestRaster r;
    r.cols = r.rows = side;
    r.geotransform = {500000.0, 10.0, 0, 5200000.0 + 10.0 * side, 0, -10.0};
    r.surface = [](double e, double n) {
      return 100.0 + 20.0 * std::sin(e / 60.0) * std::cos(n / 60.0);
    };
    dt::testing::WriteTestRaster(path, r);
  }
  return path;
}

// range(0): posts a side; range(1): 0 at the file's spacing, 1 bilinear at 7 m, 2 cubic at 7 m.
void BM_LoadGeoTiff(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  dt::ElevationSource s{.file = Raster(side)};
  if (state.range(1) > 0) s.spacing_m = 7.0;
  if (state.range(1) == 2) s.resampling = dt::Resampling::kCubic;
  int64_t posts = 0;
  for (auto _ : state) {
    const dt::ElevationLayout layout = dt::ProbeElevation(s);
    dt::HeightGrid g = dt::LoadElevation(s, layout);
    posts = int64_t{g.posts_x()} * g.posts_z();
    benchmark::DoNotOptimize(g.posts().data());
  }
  state.counters["posts"] = static_cast<double>(posts);
  // Seconds per 10^6 posts, shown as a rate's inverse.
  state.counters["s_per_Mpost"] = benchmark::Counter(
      static_cast<double>(posts) / 1e6,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_LoadGeoTiff)
    ->Args({1001, 0})
    ->Args({2001, 0})
    ->Args({1001, 1})
    ->Args({1001, 2})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
