// Benchmarks of the live view's model (view/view_model.h) at exercise scale: the CPU dt_view spends
// per second building and serialising the page's deltas, and the WebSocket bytes per second of
// those deltas against sending the full state (a snapshot) with every update; and what a page
// opening costs the view's loop (docs/performance.md).
#include <time.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "engine/memory_change_store.h"
#include "log/log.h"
#include "simulation/sim_cluster.h"
#include "view/view_model.h"

namespace dt {
namespace {

constexpr NodeAddress kServer{1, 100}, kA{1, 1}, kB{1, 2}, kView{1, 50};
constexpr int kTickHz = 30;  // the view ticks at the exercise's tick_hz (the demo's: 30)
constexpr int kVehicleUpdatesPerS = 10;
constexpr int kFeatureChangesPerS = 10;
constexpr int kBatch = 500;

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

// Feature i of the exercise on a 10 m lattice: 70 % craters, 29 % berms, 1 % bridges (the mix of
// render_bench's map), a bridge's ramps reaching into its neighbours' cells; a 15 m margin keeps
// them on the terrain.
FeatureParams FeatureAt(int i, int per_side) {
  const double x = 15.0 + 10.0 * (i % per_side), z = 15.0 + 10.0 * (i / per_side);
  if (i % 100 == 99) return FeatureParams::Bridge(x, z, 0.3, 3.0, 2.0, 4.0, 2.0, 1.0, 1.0);
  if (i % 100 >= 70) return FeatureParams::Berm(x, z, 0.7, 7.0, 2.0, 1.0);
  return FeatureParams::Crater(x, z, 2.0);
}

// The same feature with one parameter changed (a crater's radius, a berm's or a bridge's height),
// alternating, so every change is a real update of what the page draws.
FeatureParams Changed(FeatureParams p) {
  switch (p.type) {
    case FeatureType::kCrater:
      p.length_m[0] = p.length_m[0] == 2.0 ? 2.5 : 2.0;
      break;
    case FeatureType::kBerm:
      p.height_m[0] = p.height_m[0] == 1.0 ? 1.5 : 1.0;
      break;
    default:
      p.height_m[0] = p.height_m[0] == 1.0 ? 1.5 : 1.0;
      p.height_m[1] = p.height_m[0];
      break;
  }
  return p;
}

// A server, nodes A and B, and the view's observer replica, in virtual time (engine's SimCluster);
// A creates `features` features, B none, and every replica holds them all. A refused creation
// (the benchmark's own layout broken) throws with the feature and the reason.
struct Exercise {
  explicit Exercise(int features)
      : per_side(static_cast<int>(std::ceil(std::sqrt(features)))),
        cluster(1, HeightGrid(per_side + 4, 10.0, 5.0f), Config()) {
    cluster.Start(kServer, NodeRole::kServer, &store);
    cluster.Start(kA, NodeRole::kNode);
    cluster.Start(kB, NodeRole::kNode);
    cluster.Start(kView, NodeRole::kObserver);
    cluster.Run(2000);  // signed on (after silence_ms)
    for (int i = 0; i < features;) {
      for (int end = std::min(features, i + kBatch); i < end; ++i) {
        auto id = cluster.at(kA).Create(FeatureAt(i, per_side));
        if (!id) throw std::runtime_error(fmt::format("feature {}: {}", i, id.error().message));
        ids.push_back(id.value());
      }
      cluster.Run(250);  // stored and acknowledged (MaxFeature period 200 ms)
    }
    cluster.Run(1000);
  }
  static ReplicaConfig Config() {
    ReplicaConfig c;
    c.max_feature_period_ms = 200;
    c.silence_ms = 800;
    c.playback_window = 1024;
    c.members = {{kServer, NodeRole::kServer},
                 {kA, NodeRole::kNode},
                 {kB, NodeRole::kNode},
                 {kView, NodeRole::kObserver}};
    return c;
  }
  Replica& view() { return cluster.at(kView); }

  int per_side;
  MemoryChangeStore store;
  testing::SimCluster cluster;
  std::vector<FeatureId> ids;
};

// One exercise per size, kept for the benchmarks after (building 10^5 takes minutes).
Exercise& ExerciseOf(int features) {
  static std::map<int, std::unique_ptr<Exercise>> exercises;
  std::unique_ptr<Exercise>& held = exercises[features];
  if (!held) held = std::make_unique<Exercise>(features);
  return *held;
}

std::vector<VehicleView> Vehicles(int n, double size_m, std::mt19937& rng) {
  std::vector<VehicleView> vehicles;
  std::uniform_real_distribution<double> place(0.0, size_m);
  for (int i = 0; i < n; ++i) {
    vehicles.push_back({fmt::format("node-{}/{}", 1 + i % 2, i / 2),
                        fmt::format("node-{}", 1 + i % 2),
                        i % 3 == 0   ? "tank"
                        : i % 3 == 1 ? "truck"
                                     : "jeep",
                        place(rng), place(rng), 0.1 * (i % 60), 8.0, i % 50 != 0});
  }
  return vehicles;
}

std::vector<ProcessRow> Rows() {
  std::vector<ProcessRow> rows;
  for (const char* name : {"server", "node-1", "node-2"}) {
    ProcessRow r;
    r.name = name;
    r.role = name[0] == 's' ? "server" : "node";
    r.reachable = r.signed_on = r.caught_up = true;
    r.silent = false;
    r.digest = "0123456789abcdef";
    r.counters = {{"sent", 1}, {"received", 2}};
    rows.push_back(std::move(r));
  }
  return rows;
}

// One iteration is one second of the view: kTickHz ticks, each running the exercise for a tick
// (not timed), then Update + dump (timed, the view thread's CPU). Every vehicle's pose changes
// kVehicleUpdatesPerS times a second, a third of them each tick (owners' updates do not arrive in
// step); kFeatureChangesPerS features, picked at random, are updated by node A each second.
// Counters: the view's CPU seconds per second (the reported time), the delta bytes per second,
// the bytes per second of a snapshot sent with every update instead, and their ratio.
void BM_ViewModelSecond(benchmark::State& state) {
  log::Init("bench", "error");
  const int vehicles_n = static_cast<int>(state.range(0));
  const int features_n = static_cast<int>(state.range(1));
  Exercise& ex = ExerciseOf(features_n);
  ViewModel model(ex.view(), {{kA, "node-1"}, {kB, "node-2"}, {kServer, "server"}});
  const std::vector<ProcessRow> rows = Rows();
  std::mt19937 rng(5);
  std::vector<VehicleView> vehicles = Vehicles(vehicles_n, 10.0 * ex.per_side, rng);
  int64_t now_ms = 1'000'000;
  if (model.Update(now_ms, rows, vehicles, 1).is_null()) state.SkipWithError("nothing noted");
  if (model.feature_count() != static_cast<size_t>(features_n)) {
    state.SkipWithError(
        fmt::format("the model holds {} features, not {}", model.feature_count(), features_n)
            .c_str());
  }
  std::uniform_int_distribution<size_t> pick(0, ex.ids.size() - 1);
  double delta_bytes = 0, full_bytes = 0, updates = 0, seconds = 0, snapshot_cpu_s = 0;
  int tick = 0;
  for (auto _ : state) {
    double cpu_s = 0, updates_now = 0;
    for (int t = 0; t < kTickHz; ++t, ++tick) {
      if (tick % (kTickHz / kFeatureChangesPerS) == 0) {
        const FeatureId id = ex.ids[pick(rng)];
        Replica& a = ex.cluster.at(kA);
        const Record& r = a.records().all().at(id);
        if (!a.Modify(id, Changed(r.params))) state.SkipWithError("modify refused");
      }
      for (int i = tick % (kTickHz / kVehicleUpdatesPerS); i < vehicles_n;
           i += kTickHz / kVehicleUpdatesPerS) {
        VehicleView& v = vehicles[static_cast<size_t>(i)];
        v.x_m += 0.8 * std::cos(v.heading_rad);
        v.z_m += 0.8 * std::sin(v.heading_rad);
      }
      ex.cluster.Run(1000 / kTickHz);
      now_ms += 1000 / kTickHz;
      const double start = ThreadCpuSeconds();
      std::string text, frame;
      {
        // As dt_view: the known vehicles' moves in the binary vehicle message.
        const nlohmann::json delta = model.Update(now_ms, rows, vehicles, 1, &frame);
        if (!delta.is_null()) text = delta.dump();
      }  // freeing the delta counts too
      cpu_s += ThreadCpuSeconds() - start;
      if (!text.empty() || !frame.empty()) {
        delta_bytes += static_cast<double>(text.size() + frame.size());
        ++updates_now;
      }
    }
    state.SetIterationTime(cpu_s);
    // The full state, as a page would receive it with every update instead of the deltas: its
    // size (one snapshot a second, counted once per update: it barely changes within a second)
    // and its cost.
    const double start = ThreadCpuSeconds();
    const size_t snapshot_bytes = model.Snapshot(now_ms).dump().size();
    snapshot_cpu_s += ThreadCpuSeconds() - start;
    full_bytes += static_cast<double>(snapshot_bytes) * updates_now;
    updates += updates_now;
    seconds += 1;
  }
  state.counters["delta_B_per_s"] = delta_bytes / seconds;
  state.counters["full_B_per_s"] = full_bytes / seconds;
  state.counters["delta_over_full"] = delta_bytes / full_bytes;
  state.counters["deltas_per_s"] = updates / seconds;
  state.counters["snapshot_cpu_ms"] = 1000.0 * snapshot_cpu_s / seconds;
  state.counters["features"] = static_cast<double>(model.feature_count());
}
BENCHMARK(BM_ViewModelSecond)
    ->Args({10000, 100000})
    ->Args({0, 100000})
    ->Args({10000, 1000})
    ->Args({1000, 10000})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

// A page opening while the view's loop runs: the loop (a thread of its own, as dt_view's) ticks
// at kTickHz, each tick taking the publish lock for Update and dump (view/web_server.h Publish)
// while a third of the vehicles move; each iteration opens one page as WebServer::WsReady does:
// the model's Copy() under the lock, the snapshot's text after it (range(2) = 0), or, for
// comparison, the text written under the lock as well (range(2) = 1). The time reported is the
// snapshot's, from asking for the lock to the text; counters: the time the page holds the lock,
// wall and its thread's CPU (locked_ms, locked_cpu_ms), the text's size, and the loop's longest
// wait for the lock and longest tick while pages opened (loop_max_wait_ms, loop_max_tick_ms).
void BM_PageOpening(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  log::Init("bench", "error");
  const int vehicles_n = static_cast<int>(state.range(0));
  Exercise& ex = ExerciseOf(static_cast<int>(state.range(1)));
  const bool text_under_lock = state.range(2) != 0;
  ViewModel model(ex.view(), {{kA, "node-1"}, {kB, "node-2"}, {kServer, "server"}});
  const std::vector<ProcessRow> rows = Rows();
  std::mt19937 rng(5);
  std::vector<VehicleView> vehicles = Vehicles(vehicles_n, 10.0 * ex.per_side, rng);
  int64_t now_ms = 1'000'000;
  model.Update(now_ms, rows, vehicles, 1);
  std::mutex publish;
  std::atomic<bool> stop{false};
  double max_wait_ms = 0, max_tick_ms = 0;
  std::thread loop([&] {
    auto next = Clock::now();
    for (int tick = 0; !stop; ++tick) {
      next += std::chrono::milliseconds(1000 / kTickHz);
      for (int i = tick % 3; i < vehicles_n; i += 3) {
        vehicles[static_cast<size_t>(i)].x_m += 0.1;
      }
      const auto asked = Clock::now();
      {
        std::lock_guard lock(publish);
        const auto got = Clock::now();
        now_ms += 1000 / kTickHz;
        std::string frame;
        const nlohmann::json delta = model.Update(now_ms, rows, vehicles, 1, &frame);
        const std::string text = delta.is_null() ? std::string() : delta.dump();
        benchmark::DoNotOptimize(text.data());
        benchmark::DoNotOptimize(frame.data());
        max_wait_ms = std::max(max_wait_ms, ms(got - asked));
      }
      max_tick_ms = std::max(max_tick_ms, ms(Clock::now() - asked));
      std::this_thread::sleep_until(next);
    }
  });
  double locked_ms = 0, locked_cpu_ms = 0, bytes = 0, n = 0;
  for (auto _ : state) {
    const auto asked = Clock::now();
    std::string text;
    std::unique_lock lock(publish);
    const auto got = Clock::now();
    const double cpu_at = ThreadCpuSeconds();
    const int64_t at_ms = now_ms;
    const SnapshotCopy copy = model.Copy();
    if (text_under_lock) text = copy.Text(at_ms, nlohmann::json::object());
    locked_cpu_ms += 1000.0 * (ThreadCpuSeconds() - cpu_at);
    const auto released = Clock::now();
    lock.unlock();
    if (!text_under_lock) text = copy.Text(at_ms, nlohmann::json::object());
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - asked).count());
    locked_ms += ms(released - got);
    bytes += static_cast<double>(text.size());
    ++n;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the loop ticks between pages
  }
  stop = true;
  loop.join();
  state.counters["locked_ms"] = locked_ms / n;
  state.counters["locked_cpu_ms"] = locked_cpu_ms / n;
  state.counters["snapshot_MB"] = bytes / n / 1e6;
  state.counters["loop_max_wait_ms"] = max_wait_ms;
  state.counters["loop_max_tick_ms"] = max_tick_ms;
}
BENCHMARK(BM_PageOpening)
    ->Args({30000, 100000, 0})
    ->Args({30000, 100000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
