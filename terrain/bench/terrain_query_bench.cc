// Benchmarks of elevation queries (bare, craters, and a ditch over a crater below the ground in a
// mud area), six-point orientation and crater add/remove on terrains holding 10^5 and 10^6
// craters at 128 per km^2, the memory each crater costs, and adding craters to a growing terrain
// as the protocol benchmarks' replicas do.
#include <malloc.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "terrain/crater.h"
#include "terrain/terrain.h"

namespace dt {
namespace {

constexpr double kCratersPerKm2 = 128.0;
constexpr double kSpacingM = 125.0;  // the thesis's coarsest display resolution
constexpr NodeAddress kOrigin{1, 1};

// A terrain with `count` craters of radius 2..10 m scattered uniformly at 128 per km^2, plus a
// cluster of four overlapping craters at its centre for the overlap query.
struct CraterField {
  std::unique_ptr<Terrain> terrain;
  double size_m = 0.0;
  double bytes_per_crater = 0.0;
  uint32_t next_number = 1;
  std::vector<std::pair<double, double>> bare_points;  // in squares with no feature
  std::vector<std::pair<double, double>> one_points;   // covered by exactly one crater
  std::vector<std::pair<double, double>> four_points;  // covered by the four-crater cluster
  // Covered by a ditch, a crater below the ground and a mud area at once.
  std::vector<std::pair<double, double>> mixed_points;
};

size_t HeapInUse() { return mallinfo2().uordblks; }

CraterField& Field(int64_t count) {
  static std::map<int64_t, std::unique_ptr<CraterField>> fields;
  auto& slot = fields[count];
  if (slot) return *slot;
  slot = std::make_unique<CraterField>();
  CraterField& f = *slot;
  const double area_km2 = static_cast<double>(count) / kCratersPerKm2;
  const int squares = static_cast<int>(std::ceil(std::sqrt(area_km2) * 1000.0 / kSpacingM));
  f.terrain = std::make_unique<Terrain>(HeightGrid(squares + 1, kSpacingM, 50.0f));
  f.size_m = f.terrain->ground().size_x_m();  // the field is square
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pos(20.0, f.size_m - 20.0);
  std::uniform_real_distribution<double> radius(2.0, 10.0);

  const size_t heap_before = HeapInUse();
  for (int64_t k = 0; k < count; ++k) {
    const FeatureId id{kOrigin.site, kOrigin.host, f.next_number++};
    if (!f.terrain->Add(id, FeatureParams::Crater(pos(rng), pos(rng), radius(rng))).ok()) {
      std::abort();
    }
  }
  f.bytes_per_crater = static_cast<double>(HeapInUse() - heap_before) / static_cast<double>(count);

  const double cx = f.size_m / 2, cz = f.size_m / 2;
  for (int k = 0; k < 4; ++k) {
    const FeatureId id{kOrigin.site, kOrigin.host, f.next_number++};
    if (!f.terrain->Add(id, FeatureParams::Crater(cx + 0.5 * k, cz, 9.0)).ok()) std::abort();
  }
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  while (f.four_points.size() < 4096) {
    const double x = cx + 1.5 + 2.0 * unit(rng), z = cz + 2.0 * unit(rng);
    int covering = 0;
    for (const Feature* feature : f.terrain->FeaturesNear(x, z)) covering += feature->Covers(x, z);
    if (covering == 4) f.four_points.emplace_back(x, z);
  }
  // A ditch (3 points, a spoil berm), a crater 3 m deep and a mud area over one spot.
  const double mx = f.size_m / 4, mz = f.size_m / 4;
  const FeatureId ditch{kOrigin.site, kOrigin.host, f.next_number++};
  const FeatureId deep{kOrigin.site, kOrigin.host, f.next_number++};
  const FeatureId mud{kOrigin.site, kOrigin.host, f.next_number++};
  if (!f.terrain
           ->Add(ditch,
                 FeatureParams::Ditch(
                     {{mx - 40, mz, 2.5, 8}, {mx + 10, mz + 2, 2.5, 8}, {mx + 40, mz + 20, 2, 7}},
                     2.0, 1.0, 3.0))
           .ok() ||
      !f.terrain->Add(deep, FeatureParams::DeepCrater(mx, mz + 2, 8.0, 3.0)).ok() ||
      !f.terrain
           ->Add(mud, FeatureParams::Area({{mx - 30, mz - 30, 0, 0},
                                           {mx + 30, mz - 30, 0, 0},
                                           {mx + 30, mz + 30, 0, 0},
                                           {mx - 30, mz + 30, 0, 0}},
                                          Material::kMud))
           .ok()) {
    std::abort();
  }
  while (f.mixed_points.size() < 4096) {
    const double x = mx + 6.0 * unit(rng), z = mz + 1.0 + 3.0 * unit(rng);
    const Terrain& t = *f.terrain;
    if (t.Find(ditch)->Covers(x, z) && t.Find(deep)->Covers(x, z) && t.Find(mud)->Covers(x, z)) {
      f.mixed_points.emplace_back(x, z);
    }
  }
  while (f.bare_points.size() < 4096 || f.one_points.size() < 4096) {
    const double x = pos(rng), z = pos(rng);
    const auto near = f.terrain->FeaturesNear(x, z);
    if (near.empty() && f.bare_points.size() < 4096) f.bare_points.emplace_back(x, z);
    if (near.size() == 1 && f.one_points.size() < 4096) {
      // Move the point inside the one crater of this square.
      const auto* crater = dynamic_cast<const Crater*>(near[0]);
      const double px = crater->x_m() + 0.5 * crater->radius_m() * unit(rng);
      const double pz = crater->z_m() + 0.5 * crater->radius_m() * unit(rng);
      if (f.terrain->FeaturesNear(px, pz).size() == 1) f.one_points.emplace_back(px, pz);
    }
  }
  return f;
}

void Query(benchmark::State& state, std::vector<std::pair<double, double>> CraterField::*set) {
  CraterField& f = Field(state.range(0));
  const auto& points = f.*set;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [x, z] = points[k++ & 4095];
    benchmark::DoNotOptimize(f.terrain->ElevationAt(x, z));
  }
  state.counters["bytes_per_crater"] = f.bytes_per_crater;
}

void BM_QueryBareSquare(benchmark::State& state) { Query(state, &CraterField::bare_points); }
void BM_QueryOneCrater(benchmark::State& state) { Query(state, &CraterField::one_points); }
void BM_QueryFourCraters(benchmark::State& state) { Query(state, &CraterField::four_points); }
void BM_QueryDitchDeepCraterArea(benchmark::State& state) {
  Query(state, &CraterField::mixed_points);
}

void BM_AddRemoveCrater(benchmark::State& state) {
  CraterField& f = Field(state.range(0));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(20.0, f.size_m - 20.0);
  const FeatureId id{kOrigin.site, kOrigin.host, 0xFFFFFFF0u};
  for (auto _ : state) {
    if (!f.terrain->Add(id, FeatureParams::Crater(pos(rng), pos(rng), 6.0)).ok()) std::abort();
    if (!f.terrain->Remove(id).ok()) std::abort();
  }
}

// Per iteration: a fresh 1001 x 1001 terrain at 10 m (not timed), then range(0) craters of
// radius 2 m added on the 10 m lattice of posts, the protocol benchmarks' features
// (simulation/bench/lcm_cluster.h BenchCrater): each touches the four squares around its post and
// shares each square with three neighbours, and the terrain's tables grow from empty.
void BM_AddLatticeCraters(benchmark::State& state) {
  const int64_t count = state.range(0);
  std::vector<FeatureParams> craters;
  craters.reserve(static_cast<size_t>(count));
  for (int64_t n = 0; n < count; ++n) {
    craters.push_back(FeatureParams::Crater(100 + static_cast<double>(n % 980) * 10.0,
                                            100 + static_cast<double>((n / 980) % 980) * 10.0, 2));
  }
  for (auto _ : state) {
    state.PauseTiming();
    auto terrain = std::make_unique<Terrain>(HeightGrid(1001, 10.0, 5.0f));
    state.ResumeTiming();
    for (int64_t n = 0; n < count; ++n) {
      const FeatureId id{kOrigin.site, kOrigin.host, static_cast<uint32_t>(n + 1)};
      if (!terrain->Add(id, craters[static_cast<size_t>(n)]).ok()) std::abort();
    }
    state.PauseTiming();
    terrain.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * count);
}

BENCHMARK(BM_QueryBareSquare)->Arg(100'000)->Arg(1'000'000);
BENCHMARK(BM_QueryOneCrater)->Arg(100'000)->Arg(1'000'000);
BENCHMARK(BM_QueryFourCraters)->Arg(100'000)->Arg(1'000'000);
BENCHMARK(BM_QueryDitchDeepCraterArea)->Arg(100'000)->Arg(1'000'000);
BENCHMARK(BM_AddRemoveCrater)->Arg(100'000)->Arg(1'000'000);
BENCHMARK(BM_AddLatticeCraters)->Arg(100'000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
