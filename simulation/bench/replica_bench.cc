// Benchmarks of the protocol engine: features/s from one node to another over SimNetwork, and the
// server's apply rate with SQLite durability against the same apply in memory.
#include <unistd.h>

#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "engine/change_log.h"
#include "engine/memory_change_store.h"
#include "engine/record_store.h"
#include "log/log.h"
#include "server/sqlite_change_store.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

constexpr int kBatch = 200;

// Node A creates kBatch craters, then destroys them; node B applies all; a server (in memory)
// acknowledges so A's window of unacknowledged changes never fills. Items: changes applied on B.
void BM_NodeToNodeOverSimNetwork(benchmark::State& state) {
  log::Init("bench", "error");
  ReplicaConfig rc;
  rc.max_feature_period_ms = 100;
  rc.silence_ms = 400;
  rc.playback_retry_ms = 200;
  rc.playback_window = 1024;
  MemoryChangeStore store;
  testing::SimCluster cluster(1, HeightGrid(129, 8.0, 5.0f), rc);
  const NodeAddress a{1, 1}, b{1, 2}, s{1, 100};
  cluster.Start(s, NodeRole::kServer, &store);
  cluster.Start(a, NodeRole::kNode);
  cluster.Start(b, NodeRole::kNode);
  cluster.Run(1000);
  Replica& ra = cluster.at(a);
  Replica& rb = cluster.at(b);
  uint64_t applied_before = rb.counters().applied;
  for (auto _ : state) {
    std::vector<FeatureId> ids;
    for (int i = 0; i < kBatch; ++i) {
      auto id = ra.Create(FeatureParams::Crater(20 + 4.5 * i, 500, 2));
      if (!id) state.SkipWithError(id.error().message.c_str());
      ids.push_back(id.value());
    }
    cluster.Run(10);
    for (FeatureId id : ids) {
      if (!ra.Destroy(id)) state.SkipWithError("destroy refused");
    }
    cluster.Run(200);  // delivered, stored and acknowledged
  }
  const uint64_t applied = rb.counters().applied - applied_before;
  if (applied != static_cast<uint64_t>(state.iterations()) * 2 * kBatch) {
    state.SkipWithError("B missed changes");
  }
  state.SetItemsProcessed(static_cast<int64_t>(applied));
}
BENCHMARK(BM_NodeToNodeOverSimNetwork)->Unit(benchmark::kMillisecond);

// What the server does per accepted change (log insert, record apply and materialisation) plus
// the store's Append of the tick's batch: range(0) = 0 in memory, 1 SQLite (WAL, synchronous=FULL,
// one transaction per batch of kBatch). The ratio of the two rates is the cost of durability.
void BM_ServerApply(benchmark::State& state) {
  const bool durable = state.range(0) == 1;
  const auto path = std::filesystem::temp_directory_path() /
                    fmt::format("dt_replica_bench_{}.db", static_cast<long>(::getpid()));
  std::filesystem::remove(path);
  std::unique_ptr<ChangeStore> store;
  if (durable) {
    const HeightGrid ground(129, 8.0, 5.0f);
    auto s = SqliteChangeStore::Open(path, ground.size_x_m(), ground.size_z_m());
    if (!s) {
      state.SkipWithError(s.error().message.c_str());
      return;
    }
    store = std::move(s).value();
  } else {
    store = std::make_unique<MemoryChangeStore>();
  }
  RecordStore records(HeightGrid(129, 8.0, 5.0f));
  ChangeLog log;
  uint32_t seq = 0, number = 0;
  for (auto _ : state) {
    std::vector<Change> batch;
    for (int i = 0; i < kBatch; ++i) {
      Change c;
      c.kind = ChangeKind::kConstruct;
      c.id = {1, 1, ++number};
      c.params = FeatureParams::Crater(20 + 4.5 * i, 20 + (number / kBatch) % 200 * 5.0, 2);
      c.stamp.changed_by = {1, 1};
      c.stamp.change_seq = ++seq;
      c.stamp.lamport = seq;
      if (log.Insert(c)) (void)records.Apply(c);
      batch.push_back(std::move(c));
    }
    if (auto s = store->Append(batch); !s) state.SkipWithError(s.error().message.c_str());
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  store.reset();
  std::filesystem::remove(path);
  std::filesystem::remove(path.string() + "-wal");
  std::filesystem::remove(path.string() + "-shm");
}
BENCHMARK(BM_ServerApply)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace dt

BENCHMARK_MAIN();
