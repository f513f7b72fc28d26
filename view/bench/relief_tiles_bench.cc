// Benchmarks of the live view's relief tiles (view/relief_tiles.h) on a 50 km world of 5001 x 5001
// posts (25 M, 10 m apart) with 10^5 craters: a tile's sample (the view's loop) and drawing (the
// tiles' thread) at each level, the relief's update after one crater, and a page opening (time to
// its first complete picture). docs/performance.md "view: relief tiles".
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>

#include "log/log.h"
#include "render/renderer.h"
#include "view/relief_tiles.h"

namespace dt {
namespace {

constexpr int kPosts = 5001;
constexpr double kSpacingM = 10.0;
constexpr int kCraters = 100000;
constexpr size_t kTilesPerTick = 4;  // as dt_view (view_app.h)

Terrain& World() {
  static Terrain* world = [] {
    log::Init("bench", "error");
    // Random ground stops at 4097 posts a side: hills of 2 km to 40 m, an analytic surface.
    std::vector<float> posts(static_cast<size_t>(kPosts) * kPosts);
    for (int j = 0; j < kPosts; ++j) {
      for (int i = 0; i < kPosts; ++i) {
        posts[static_cast<size_t>(j) * kPosts + i] = static_cast<float>(
            150.0 + 100.0 * std::sin(i * 0.005) * std::cos(j * 0.004) +
            10.0 * std::sin(i * 0.11 + j * 0.07) + 2.0 * std::cos(i * 0.9) * std::sin(j * 0.8));
      }
    }
    auto* t = new Terrain(HeightGrid(kPosts, kSpacingM, std::move(posts)));
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> at(100.0, (kPosts - 1) * kSpacingM - 100.0);
    std::uniform_real_distribution<double> radius(3.0, 30.0);
    for (uint32_t k = 1; k <= kCraters; ++k)
      (void)t->Add({2, 1, k}, FeatureParams::Crater(at(rng), at(rng), radius(rng)));
    return t;
  }();
  return *world;
}

std::pair<double, double> Range(const ReliefPyramid& p) {
  static const auto range = SampledElevationRange(World().ground(), p);
  return range;
}

// The view's loop: serves the pages' tiles until `done`, as dt_view's tick does.
template <typename Done>
void PlayLoop(ReliefTiles& tiles, const Terrain& t, Done done) {
  while (!done()) {
    tiles.Serve(t, kTilesPerTick);
    std::this_thread::yield();
  }
}

// Pages asking for `keys` at once (each from a thread of its own, as civetweb's); returns when
// every tile is answered, and the seconds until the first key's answer.
double AskAll(ReliefTiles& tiles, const Terrain& t, const std::vector<TileKey>& keys) {
  const auto start = std::chrono::steady_clock::now();
  double first_s = -1.0;
  std::vector<std::future<ReliefTiles::Answer>> pages;
  for (const TileKey& k : keys)
    pages.push_back(std::async(std::launch::async, [&tiles, k] { return tiles.Get(k, 60000); }));
  size_t answered = 0;
  PlayLoop(tiles, t, [&] {
    answered = 0;
    for (auto& p : pages)
      answered += p.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    if (first_s < 0.0 &&
        pages.front().wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      first_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return answered == pages.size();
  });
  for (auto& p : pages) {
    if (p.get().status != 200) throw std::runtime_error("a relief tile was not drawn");
  }
  return first_s;
}

// A tile in the middle of the world at each level: its sample on the loop.
void BM_TileSample(benchmark::State& state) {
  const Terrain& t = World();
  const ReliefPyramid p(t.ground().size_x_m(), t.ground().size_z_m(), kSpacingM);
  const int level = static_cast<int>(state.range(0));
  const int mid = (1 << level) / 2;
  for (auto _ : state) {
    ReliefTileJob job = SampleReliefTile(t, p, {level, mid, mid}, 1, Range(p));
    benchmark::DoNotOptimize(job);
    state.counters["posts"] = static_cast<double>(job.ground.post_count());
    state.counters["features"] = static_cast<double>(job.features.size());
  }
  state.counters["levels"] = p.levels();
}
BENCHMARK(BM_TileSample)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);

// The same tile drawn (OSMesa) and encoded as PNG: the tiles' thread.
void BM_TileRender(benchmark::State& state) {
  const Terrain& t = World();
  const ReliefPyramid p(t.ground().size_x_m(), t.ground().size_z_m(), kSpacingM);
  const int level = static_cast<int>(state.range(0));
  const int mid = (1 << level) / 2;
  const ReliefTileJob job = SampleReliefTile(t, p, {level, mid, mid}, 1, Range(p));
  Renderer renderer;
  size_t bytes = 0;
  for (auto _ : state) {
    auto png = RenderReliefTile(renderer, job);
    if (!png) throw std::runtime_error(png.error().message);
    bytes = png.value().size();
  }
  state.counters["png_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_TileRender)->DenseRange(0, 5)->Unit(benchmark::kMillisecond);

// One crater, then every tile it changed drawn again (at every level: a page shows one level,
// so it waits for fewer): the terrain's change to the tiles' versions (Track) and the tiles
// sampled and drawn. Manual time: the crater's removal between runs is not timed.
void BM_ReliefUpdateAfterOneCrater(benchmark::State& state) {
  Terrain& t = World();
  ReliefTiles tiles(t.ground());
  (void)tiles.Track(t);
  uint32_t n = 0;
  size_t changed = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const FeatureId id{3, 1, ++n};
    (void)t.Add(id, FeatureParams::Crater(20012.0 + n, 30007.0, 25.0));
    const nlohmann::json m = tiles.Track(t);
    std::vector<TileKey> keys;
    for (const auto& [k, v] : m["versions"].items())
      keys.push_back(ParseTileKey(k, tiles.pyramid()).value());
    AskAll(tiles, t, keys);
    state.SetIterationTime(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    changed = keys.size();
    (void)t.Remove(id);
    (void)tiles.Track(t);
  }
  state.counters["tiles"] = static_cast<double>(changed);
}
BENCHMARK(BM_ReliefUpdateAfterOneCrater)->UseManualTime()->Unit(benchmark::kMillisecond);

// A page opening on the whole world in a 1280 x 800 window: level 0 and the 4 x 4 tiles of
// level 2 (12.5 km, 49 m a pixel: the first level no coarser than the window's 62.5 m), from a
// cold cache, to the last tile answered: its first complete picture (`first_tile_ms`: level 0's
// tile, the whole world coarse, which the page shows first). The page's snapshot is
// view_model_bench's.
void BM_PageOpening(benchmark::State& state) {
  const Terrain& t = World();
  std::vector<TileKey> keys{{0, 0, 0}};
  for (int tz = 0; tz < 4; ++tz)
    for (int tx = 0; tx < 4; ++tx) keys.push_back({2, tx, tz});
  double first_s = 0.0;
  for (auto _ : state) {
    ReliefTiles tiles(t.ground());
    (void)tiles.Track(t);
    first_s += AskAll(tiles, t, keys);
  }
  state.counters["tiles"] = static_cast<double>(keys.size());
  state.counters["first_tile_ms"] = 1000.0 * first_s / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PageOpening)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
