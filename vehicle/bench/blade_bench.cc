// The bulldozer's blade work (docs/performance.md "Blade work"): a dozer driving at 1.5 m/s with
// its blade 0.2 m down, raised for 2 s every 12 s to set its load down, stepped at the node's
// 30 Hz tick over 1 m and 0.5 m grids. Counters: post changes per second of simulated time, the
// EarthMove bytes per second on the wire (LCM encoding plus the authentication trailer)
// against sending each touched region whole, as a PDU of the same header holding a 4-byte float
// per post instead of the mask and the deltas: the region is either the rectangle of the tick's
// changed posts (`whole`, per earth move) or the window the blade worked in that tick
// (`window`: the blade, its reach and the slump's margin, on ticks that changed a post); on a
// receiver the cost of
// adding the earth moves to its terrain, per post change. BM_BladeTick's time is the author's
// blade step per tick; BM_ApplyEarthMoves' is a receiver's apply of one tick's earth moves.
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "pdu/auth_trailer.h"
#include "pdu/conversion.h"
#include "pdu/pdu_traits.h"
#include "terrain/random_terrain.h"
#include "terrain/slump.h"
#include "terrain/terrain.h"
#include "vehicle/blade.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/vehicle_type.h"

namespace dt {
namespace {

constexpr double kTickS = 1.0 / 30.0;
constexpr double kSpeedMps = 1.5;
constexpr double kSeconds = 60.0;

HeightGrid Ground(double spacing_m) {
  RandomTerrainParams p;
  p.spacing_m = spacing_m;
  p.posts_x = p.posts_z = static_cast<int>(std::lround(200.0 / spacing_m)) + 1;
  p.relief_m = 3.0;
  p.seed = 11;
  return MakeRandomTerrain(p);
}

struct Tick {
  std::vector<std::vector<PostDelta>> moves;
  int window_posts = 0;  // the posts the blade worked in this tick
};

// Drives the dozer for kSeconds across a fresh terrain, adding its work as it goes; returns the
// earth moves of every tick.
std::vector<Tick> Drive(Terrain& t) {
  Blade blade(BladeOf("bulldozer").value());
  std::vector<Tick> ticks;
  double x = 20.0;
  const double z = 100.0;
  uint32_t number = 0;
  const int n = static_cast<int>(kSeconds / kTickS);
  for (int k = 0; k < n; ++k) {
    const double s = k * kTickS;
    const bool down = std::fmod(s, 12.0) < 10.0;
    if (down && !blade.down()) (void)blade.Lower(0.2);
    if (!down && blade.down()) blade.Raise();
    x += kSpeedMps * kTickS;
    Tick tick;
    const auto deltas = blade.Step(t, ShippedFrictionTable(), x, z, 0.0, BulldozerType().length_m);
    tick.window_posts = blade.last_window_posts();
    for (auto& piece : SplitEarthMove(deltas)) {
      if (!t.Add({1, 1, ++number}, FeatureParams::EarthMove(piece)).ok()) std::abort();
      tick.moves.push_back(std::move(piece));
    }
    ticks.push_back(std::move(tick));
  }
  return ticks;
}

size_t WireBytes(const std::vector<PostDelta>& move) {
  FeaturePdu f{{1, 1, 1}, FeatureParams::EarthMove(move), {{1, 1}, 1, 1}};
  return EncodePdu(ToEarthMove(f)).size() + kAuthTrailerBytes;
}

size_t WholeRegionBytes(const std::vector<PostDelta>& move) {
  FeaturePdu f{{1, 1, 1}, FeatureParams::EarthMove(move), {{1, 1}, 1, 1}};
  dtpdu::earth_move_t pdu = ToEarthMove(f);
  const size_t posts = static_cast<size_t>(pdu.columns) * static_cast<size_t>(pdu.rows);
  pdu.num_mask_bytes = 0;
  pdu.changed_mask.clear();
  pdu.num_posts = 0;
  pdu.delta_mm.clear();
  return EncodePdu(pdu).size() + 4 * posts + kAuthTrailerBytes;
}

void BM_BladeTick(benchmark::State& state) {
  const double spacing_m = static_cast<double>(state.range(0)) / 10.0;
  int64_t changes = 0, ticks = 0, pdus = 0;
  size_t wire = 0, whole = 0, window = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Terrain t(Ground(spacing_m));
    state.ResumeTiming();
    const auto driven = Drive(t);
    state.PauseTiming();
    for (const Tick& tick : driven) {
      ++ticks;
      // The blade's window whole, in a PDU of the same header, on every tick that changed a post.
      if (!tick.moves.empty()) {
        window += WholeRegionBytes({tick.moves.front().front()}) - 4 +
                  4 * static_cast<size_t>(tick.window_posts);
      }
      for (const auto& move : tick.moves) {
        changes += static_cast<int64_t>(move.size());
        ++pdus;
        wire += WireBytes(move);
        whole += WholeRegionBytes(move);
      }
    }
    state.ResumeTiming();
  }
  const double sim_s = static_cast<double>(ticks) * kTickS;
  state.counters["post_changes_per_s"] = static_cast<double>(changes) / sim_s;
  state.counters["pdus_per_s"] = static_cast<double>(pdus) / sim_s;
  state.counters["wire_bytes_per_s"] = static_cast<double>(wire) / sim_s;
  state.counters["whole_bytes_per_s"] = static_cast<double>(whole) / sim_s;
  state.counters["wire_over_whole"] = static_cast<double>(wire) / static_cast<double>(whole);
  state.counters["window_bytes_per_s"] = static_cast<double>(window) / sim_s;
  state.counters["wire_over_window"] = static_cast<double>(wire) / static_cast<double>(window);
  state.counters["us_per_tick"] = benchmark::Counter(
      static_cast<double>(ticks) * 1e-6, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_BladeTick)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_ApplyEarthMoves(benchmark::State& state) {
  const double spacing_m = static_cast<double>(state.range(0)) / 10.0;
  Terrain author(Ground(spacing_m));
  const auto driven = Drive(author);
  std::vector<FeatureParams> moves;
  int64_t posts = 0;
  for (const Tick& tick : driven) {
    for (const auto& move : tick.moves) {
      moves.push_back(FeatureParams::EarthMove(move));
      posts += static_cast<int64_t>(move.size());
    }
  }
  Terrain receiver(Ground(spacing_m));
  int64_t applied = 0;
  for (auto _ : state) {
    // Every earth move added, then taken off again: the receiver's ground is back where it
    // began, so each iteration does the same work.
    uint32_t number = 0;
    for (const auto& p : moves) {
      if (!receiver.Add({1, 1, ++number}, p).ok()) std::abort();
    }
    for (uint32_t k = 1; k <= number; ++k) (void)receiver.Remove({1, 1, k});
    applied += 2 * posts;
  }
  state.counters["ns_per_post_change"] =
      benchmark::Counter(static_cast<double>(applied) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["earth_moves"] = static_cast<double>(moves.size());
}
BENCHMARK(BM_ApplyEarthMoves)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
