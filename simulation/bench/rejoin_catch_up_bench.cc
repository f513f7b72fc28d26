// Benchmark of a rejoin: a node with no local state catches up 10^4 or 10^5 features by Playback
// from the origin or the server, against a raw LCM transfer of the same messages in the same run.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/memory_change_store.h"
#include "simulation/bench/lcm_cluster.h"
#include "transport/bench/bench_main.h"
#include "transport/bench/raw_lcm_link.h"

namespace dt {
namespace {

const NodeAddress kA{1, 1}, kB{1, 2}, kServer{1, 100};
using bench::PumpUntil;

// range(0) features; range(1) = 0: origin A alive (it is asked first), 1: A gone, the server
// answers; range(2) = tick period during the catch-up (0: after every dispatch; 33: node_main's
// 30 Hz). Every replica runs the protocol defaults (playback_window 256: one window per round
// trip) except A's window of unacknowledged changes, raised so the setup is quick. Setup (not
// timed): server, A and B sign on, B crashes, A creates the features and the server stores them.
// Timed (manual): from B's restart with no state until B holds all of A's changes. Then the
// Construct messages that crossed LCM during the catch-up are sent again, the same bytes, by raw
// LCM publish and receive in batches of 256; ratio = catch-up time / raw time.
void BM_RejoinCatchUp(benchmark::State& state) {
  const int64_t n = state.range(0);
  const bool from_server = state.range(1) == 1;
  const int64_t tick_ms = state.range(2);
  const ReplicaConfig defaults;
  double catch_up_s = 0, raw_s = 0, messages = 0, raw_lost = 0, by_origin = 0, by_server = 0;
  double b_ns = 0, origin_ns = 0, server_ns = 0;
  for (auto _ : state) {
    MemoryChangeStore store;
    bench::LcmCluster cluster("memq://", bench::BenchGround(), defaults);
    Replica& server = cluster.Start(kServer, NodeRole::kServer, &store);
    ReplicaConfig origin = defaults;
    origin.playback_window = static_cast<int>(kMaxPlaybackSpan);
    Replica& a = cluster.Start(kA, NodeRole::kNode, nullptr, origin);
    cluster.Start(kB, NodeRole::kNode);
    if (!PumpUntil(cluster, 20000, [&] { return a.signed_on() && cluster.at(kB).signed_on(); })) {
      state.SkipWithError("A and B did not sign on");
      return;
    }
    cluster.Crash(kB);
    for (int64_t i = 0; i < n;) {
      if (a.Create(bench::BenchCrater(i))) {
        if (++i % 500 == 0) cluster.Pump(0);
      } else {
        cluster.Pump(1);  // a full window: wait for the server's acknowledgement
      }
    }
    if (!PumpUntil(cluster, 60000, [&] {
          auto d = server.durable_change_seq();
          return d.count(kA) != 0 && d.at(kA) >= n;
        })) {
      state.SkipWithError("the server did not store every change");
      return;
    }
    if (from_server) cluster.Crash(kA);
    const uint64_t origin_played = from_server ? 0 : a.counters().played_back;
    const uint64_t server_played = server.counters().played_back;
    const int64_t origin_ns0 = from_server ? 0 : cluster.ReceiveNs(kA);
    const int64_t server_ns0 = cluster.ReceiveNs(kServer);

    cluster.RecordConstructs(true);
    cluster.set_tick_period_ms(tick_ms);
    const int64_t t0 = bench::SteadyNowNs();
    Replica& b = cluster.Start(kB, NodeRole::kNode);
    if (!PumpUntil(
            cluster, 120000, [&] { return b.log(kA) != nullptr && b.log(kA)->contiguous() >= n; },
            tick_ms > 0 ? 1 : 0)) {
      state.SkipWithError("B did not catch up within 120 s");
      return;
    }
    const int64_t catch_up_ns = bench::SteadyNowNs() - t0;
    // Time in each replica's handlers during the catch-up (one thread runs them all): B's
    // decode and apply; the answering replica's playback (encode, publish) and echo decoding.
    b_ns += static_cast<double>(cluster.ReceiveNs(kB));
    if (!from_server) origin_ns += static_cast<double>(cluster.ReceiveNs(kA) - origin_ns0);
    server_ns += static_cast<double>(cluster.ReceiveNs(kServer) - server_ns0);
    cluster.RecordConstructs(false);
    const auto recorded = cluster.TakeRecorded();
    if (!from_server) by_origin += static_cast<double>(a.counters().played_back - origin_played);
    by_server += static_cast<double>(server.counters().played_back - server_played);

    bench::RawLcmLink raw("memq://", ChannelName(1, PduType::kConstruct));
    const int64_t t1 = bench::SteadyNowNs();
    raw_lost += static_cast<double>(raw.Transfer(recorded, 256));
    const int64_t raw_ns = bench::SteadyNowNs() - t1;

    state.SetIterationTime(static_cast<double>(catch_up_ns) / 1e9);
    catch_up_s += static_cast<double>(catch_up_ns) / 1e9;
    raw_s += static_cast<double>(raw_ns) / 1e9;
    messages += static_cast<double>(recorded.size());
  }
  const auto iterations = static_cast<double>(state.iterations());
  state.counters["catch_up_ms"] = catch_up_s / iterations * 1000.0;
  state.counters["raw_ms"] = raw_s / iterations * 1000.0;
  state.counters["ratio"] = catch_up_s / raw_s;
  state.counters["messages"] = messages / iterations;
  state.counters["raw_lost"] = raw_lost;
  state.counters["played_by_origin"] = by_origin / iterations;
  state.counters["played_by_server"] = by_server / iterations;
  const double changes = static_cast<double>(n) * iterations;
  state.counters["b_recv_us"] = b_ns / changes / 1000.0;
  state.counters["origin_recv_us"] = origin_ns / changes / 1000.0;
  state.counters["server_recv_us"] = server_ns / changes / 1000.0;
  state.counters["raw_us"] = raw_s / messages * 1e6;
  state.counters["features_per_s"] = static_cast<double>(n) / (catch_up_s / iterations);
}
// 10^4: three catch-ups (a transfer of 10^4 messages takes only 20-40 ms, so one is noisy).
BENCHMARK(BM_RejoinCatchUp)
    ->ArgNames({"features", "from_server", "tick_ms"})
    ->Args({10000, 0, 0})
    ->Args({10000, 1, 0})
    ->Args({10000, 1, 33})
    ->UseManualTime()
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RejoinCatchUp)
    ->ArgNames({"features", "from_server", "tick_ms"})
    ->Args({100000, 0, 0})
    ->Args({100000, 1, 0})
    ->Args({100000, 1, 33})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "rejoin-bench", "error", false);
}
