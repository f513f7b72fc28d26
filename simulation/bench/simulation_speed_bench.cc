// Benchmark of the deterministic simulation's speed: virtual exercise time per wall time on one
// core for a server and three nodes over a faulty SimNetwork, so long simulation runs can be sized.
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/memory_change_store.h"
#include "engine/record_store.h"
#include "log/log.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

constexpr NodeAddress kServer{1, 100};
constexpr int kNodes = 3;
// Live features the mix keeps around: a node creates below it and updates or destroys above.
constexpr size_t kLiveTarget = 60;
constexpr int64_t kCommandPeriodMs = 100;  // each node issues one command this often
constexpr int64_t kIterationMs = 1000;     // virtual time per benchmark iteration

// The settings protocol_sim_test runs with; faults at the middle of the ranges it draws from
// (loss up to 30 %, duplicates up to 10 %, delay up to 40 ms, reordering up to 20 %).
ReplicaConfig SimConfig() {
  ReplicaConfig rc;
  rc.max_feature_period_ms = 200;
  rc.silence_ms = 800;
  rc.playback_retry_ms = 300;
  rc.playback_window = 16;
  rc.gap_give_up_ms = 4000;
  rc.members[kServer] = NodeRole::kServer;
  for (int i = 1; i <= kNodes; ++i) rc.members[{1, static_cast<uint16_t>(i)}] = NodeRole::kNode;
  return rc;
}

FaultConfig Faults(bool faulty) {
  FaultConfig f;
  if (!faulty) return f;
  f.drop_probability = 0.15;
  f.duplicate_probability = 0.05;
  f.max_delay = 20;
  f.reorder_probability = 0.1;
  f.reorder_window = 50;
  return f;
}

// range(0): 1 over the faulty network, 0 over a perfect one. Not timed: sign-on. Measured: a
// steady mix in which every node, every 100 virtual ms, creates (a crater, a berm) while fewer than
// 60 features live, else updates or destroys one it knows, on the simulation's ground (17 posts
// 8 m apart). Counters: virtual_s = virtual s per wall s (times faster than real time); changes =
// changes issued per wall s.
void BM_SimulationSpeed(benchmark::State& state) {
  log::Init("bench", "error");
  const bool faulty = state.range(0) == 1;
  MemoryChangeStore store;
  testing::SimCluster cluster(7, HeightGrid(17, 8.0, 5.0f), SimConfig(), Faults(faulty));
  cluster.Start(kServer, NodeRole::kServer, &store);
  std::vector<NodeAddress> nodes;
  for (int i = 1; i <= kNodes; ++i) {
    nodes.push_back({1, static_cast<uint16_t>(i)});
    cluster.Start(nodes.back(), NodeRole::kNode);
  }
  for (int64_t waited = 0; waited < 10000; waited += 10) {
    bool all = true;
    for (NodeAddress a : nodes) all = all && cluster.at(a).signed_on();
    if (all) break;
    cluster.Run(10);
  }
  for (NodeAddress a : nodes) {
    if (!cluster.at(a).signed_on()) {
      state.SkipWithError("a node did not sign on");
      return;
    }
  }
  std::mt19937_64 rng(11);
  auto uniform = [&](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
  };
  std::vector<FeatureId> live;
  uint64_t issued = 0;
  const int64_t start_ms = cluster.now_ms();
  for (auto _ : state) {
    for (int64_t t = 0; t < kIterationMs; t += kCommandPeriodMs) {
      cluster.Run(kCommandPeriodMs);
      for (NodeAddress a : nodes) {
        Replica& r = cluster.at(a);
        const int64_t before = r.own_change_seq();
        const double x = uniform(15, 113), z = uniform(15, 113);
        if (live.size() < kLiveTarget) {
          auto id = rng() % 3 == 0
                        ? r.Create(FeatureParams::Berm(x, z, uniform(0, 6.28), uniform(8, 30),
                                                       uniform(2, 5), uniform(1, 3)))
                        : r.Create(FeatureParams::Crater(x, z, uniform(1, 6)));
          if (id) live.push_back(id.value());
        } else {
          const size_t i = rng() % live.size();
          const Record* rec = r.records().Find(live[i]);
          if (rec == nullptr) {
            // Not arrived here yet (a drop being repaired): try another next time.
          } else if (rng() % 2 == 0) {
            (void)r.Modify(live[i],
                           rec->params.type == FeatureType::kCrater
                               ? FeatureParams::Crater(x, z, uniform(1, 6))
                               : FeatureParams::Berm(x, z, uniform(0, 6.28), uniform(8, 30),
                                                     uniform(2, 5), uniform(1, 3)));
          } else if (r.Destroy(live[i])) {
            live[i] = live.back();
            live.pop_back();
          }
        }
        issued += static_cast<uint64_t>(r.own_change_seq() - before);
      }
    }
  }
  const double simulated_s = static_cast<double>(cluster.now_ms() - start_ms) / 1000.0;
  if (issued == 0) state.SkipWithError("no change was issued");
  state.counters["virtual_s"] = benchmark::Counter(simulated_s, benchmark::Counter::kIsRate);
  state.counters["changes"] =
      benchmark::Counter(static_cast<double>(issued), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulationSpeed)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
