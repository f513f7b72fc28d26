// Benchmark of anti-entropy on an exercise at rest holding 10^5 features: the bytes each replica
// sends and receives per second, and the time to find and repair one corrupted feature.
#include <algorithm>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/memory_change_store.h"
#include "engine/prefix_hashes.h"
#include "simulation/bench/lcm_cluster.h"
#include "transport/bench/bench_main.h"

namespace dt {
namespace {

const NodeAddress kA{1, 1}, kB{1, 2}, kServer{1, 100};

// A server, A and B over LCM memq on one thread; A has created `n` craters and every replica
// holds them all. Fast acknowledgements (bench::FastAckConfig) make the setup quick; anti-entropy
// runs at its default period (ReplicaConfig::anti_entropy_period_ms, 1000 ms).
struct AtRest {
  explicit AtRest(int64_t n) : cluster("memq://", bench::BenchGround(), bench::FastAckConfig()) {
    Replica& server = cluster.Start(kServer, NodeRole::kServer, &store);
    Replica& a = cluster.Start(kA, NodeRole::kNode);
    Replica& b = cluster.Start(kB, NodeRole::kNode);
    if (!bench::PumpUntil(cluster, 20000, [&] { return a.signed_on() && b.signed_on(); })) {
      error = "A and B did not sign on";
      return;
    }
    for (int64_t i = 0; i < n;) {
      if (a.Create(bench::BenchCrater(i))) {
        if (++i % 500 == 0) cluster.Pump(0);
      } else {
        cluster.Pump(1);  // a full window: wait for the server's acknowledgement
      }
    }
    if (!bench::PumpUntil(cluster, 60000, [&] {
          const ChangeLog* at_b = b.log(kA);
          const auto durable = server.durable_change_seq();
          return at_b != nullptr && at_b->contiguous() >= n && durable.count(kA) != 0 &&
                 durable.at(kA) >= n && b.caught_up() && server.caught_up();
        })) {
      error = "the replicas did not all hold every change";
    }
  }
  std::vector<Replica*> replicas() {
    return {&cluster.at(kServer), &cluster.at(kA), &cluster.at(kB)};
  }

  MemoryChangeStore store;
  bench::LcmCluster cluster;
  std::string error;
};

// range(0) features. Not timed: the setup, then two summary periods so each replica has hashed
// every change once. Measured: 10 s of wall time at rest (pumping with 5 ms waits, every replica
// ticking); counters per replica and second, mean over the three: AntiEntropy bytes sent and
// received, summaries sent, other AntiEntropy requests sent (0 when the logs agree).
void BM_AntiEntropyAtRest(benchmark::State& state) {
  const int64_t n = state.range(0);
  constexpr int64_t kMeasureMs = 10000;
  double sent = 0, received = 0, summaries = 0, requests = 0;
  for (auto _ : state) {
    AtRest e(n);
    if (!e.error.empty()) {
      state.SkipWithError(e.error.c_str());
      return;
    }
    const int64_t settle_until = e.cluster.now_ms() + 2000;
    bench::PumpUntil(
        e.cluster, 3000, [&] { return e.cluster.now_ms() >= settle_until; }, 5);
    std::vector<AntiEntropy::Stats> before;
    for (Replica* r : e.replicas()) before.push_back(r->anti_entropy().stats());
    const int64_t t0 = e.cluster.now_ms();
    bench::PumpUntil(
        e.cluster, kMeasureMs + 1000, [&] { return e.cluster.now_ms() - t0 >= kMeasureMs; }, 5);
    const double seconds = static_cast<double>(e.cluster.now_ms() - t0) / 1000.0;
    const auto rs = e.replicas();
    for (size_t i = 0; i < rs.size(); ++i) {
      const AntiEntropy::Stats& s = rs[i]->anti_entropy().stats();
      const AntiEntropy::Stats& b = before[i];
      sent += static_cast<double>(s.bytes_sent - b.bytes_sent) / seconds / 3;
      received += static_cast<double>(s.bytes_received - b.bytes_received) / seconds / 3;
      summaries += static_cast<double>(s.summaries_sent - b.summaries_sent) / seconds / 3;
      requests += static_cast<double>(s.hash_requests_sent + s.copy_requests_sent -
                                      b.hash_requests_sent - b.copy_requests_sent) /
                  seconds / 3;
    }
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["sent_bytes_per_s"] = sent / iterations;
  state.counters["received_bytes_per_s"] = received / iterations;
  state.counters["summaries_per_s"] = summaries / iterations;
  state.counters["requests_per_s"] = requests / iterations;
}
BENCHMARK(BM_AntiEntropyAtRest)->Arg(100000)->Iterations(1)->Unit(benchmark::kSecond);

// range(0) features. Not timed: the setup. Then 5 times: B's copy of one of A's changes (at
// 1/6, 2/6, ... of the log) gets a crater radius 1 m larger, as a damaged store would give it,
// at a random moment of the summary period (a 0-1000 ms wait first, steps of 259 ms); detect =
// from the corruption until a replica reports diverged(); repair = until B holds the server's copy
// again; settle = until, besides, no replica reports diverged (the next summaries agree). Wall
// time, every replica ticking after each dispatch; mean and max of the 5, and the digests are
// checked equal at the end.
void BM_AntiEntropyRepair(benchmark::State& state) {
  const int64_t n = state.range(0);
  constexpr int kRuns = 5;
  std::vector<double> detect_ms, repair_ms, settle_ms;
  for (auto _ : state) {
    AtRest e(n);
    if (!e.error.empty()) {
      state.SkipWithError(e.error.c_str());
      return;
    }
    Replica& server = e.cluster.at(kServer);
    Replica& b = e.cluster.at(kB);
    for (int run = 1; run <= kRuns; ++run) {
      const int64_t wait_until = e.cluster.now_ms() + (run * 259) % 1000;
      bench::PumpUntil(
          e.cluster, 2000, [&] { return e.cluster.now_ms() >= wait_until; }, 1);
      const int64_t seq = n * run / (kRuns + 1);
      Change bad = *b.log(kA)->Find(seq);
      bad.params.length_m[0] += 1.0;
      const int64_t t0 = bench::SteadyNowNs();
      if (!b.anti_entropy().Overwrite(bad).ok()) {
        state.SkipWithError("B does not hold the change to corrupt");
        return;
      }
      const auto replicas = e.replicas();
      auto any_diverged = [&] {
        return std::any_of(replicas.begin(), replicas.end(),
                           [](Replica* r) { return r->diverged(); });
      };
      if (!bench::PumpUntil(e.cluster, 10000, any_diverged)) {
        state.SkipWithError("the corruption was not found within 10 s");
        return;
      }
      const int64_t t1 = bench::SteadyNowNs();
      if (!bench::PumpUntil(e.cluster, 20000,
                            [&] { return *b.log(kA)->Find(seq) == *server.log(kA)->Find(seq); })) {
        state.SkipWithError("the corruption was not repaired within 20 s");
        return;
      }
      const int64_t t2 = bench::SteadyNowNs();
      if (!bench::PumpUntil(e.cluster, 20000, [&] { return !any_diverged(); })) {
        state.SkipWithError("a replica stayed diverged for 20 s after the repair");
        return;
      }
      const int64_t t3 = bench::SteadyNowNs();
      detect_ms.push_back(static_cast<double>(t1 - t0) / 1e6);
      repair_ms.push_back(static_cast<double>(t2 - t0) / 1e6);
      settle_ms.push_back(static_cast<double>(t3 - t0) / 1e6);
    }
    if (b.Digest() != server.Digest() || e.cluster.at(kA).Digest() != server.Digest()) {
      state.SkipWithError("the digests differ after the repairs");
      return;
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  auto max = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  state.counters["detect_ms_mean"] = mean(detect_ms);
  state.counters["detect_ms_max"] = max(detect_ms);
  state.counters["repair_ms_mean"] = mean(repair_ms);
  state.counters["repair_ms_max"] = max(repair_ms);
  state.counters["settle_ms_mean"] = mean(settle_ms);
  state.counters["settle_ms_max"] = max(settle_ms);
}
BENCHMARK(BM_AntiEntropyRepair)->Arg(100000)->Iterations(1)->Unit(benchmark::kSecond);

// What anti-entropy adds per change accepted: hashing it once into its author's prefix sums
// (PrefixHashes::Extend, at the next summary). range(0) changes, A's crater Constructs; CPU
// time per change.
void BM_PrefixHashesPerChange(benchmark::State& state) {
  const int64_t n = state.range(0);
  ChangeLog log;
  for (int64_t i = 1; i <= n; ++i) log.Insert(bench::BenchCraterConstruct(kA, i));
  for (auto _ : state) {
    PrefixHashes p;
    p.Extend(log);
    benchmark::DoNotOptimize(p.At(n));
  }
  state.counters["s_per_change"] =
      benchmark::Counter(static_cast<double>(state.iterations() * n),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_PrefixHashesPerChange)->Arg(100000)->Unit(benchmark::kMillisecond);

// The same as a replica meets it: the log grows while the exercise runs and every summary (sent,
// or received from a peer) extends the sums by what arrived since. range(0) changes in all,
// range(1) between extensions; counter: the extensions' wall time per change.
void BM_PrefixHashesGrowing(benchmark::State& state) {
  const int64_t n = state.range(0);
  const int64_t step = state.range(1);
  std::vector<Change> changes;
  changes.reserve(static_cast<size_t>(n));
  for (int64_t i = 1; i <= n; ++i) changes.push_back(bench::BenchCraterConstruct(kA, i));
  int64_t extend_ns = 0;
  for (auto _ : state) {
    ChangeLog log;
    PrefixHashes p;
    for (int64_t i = 0; i < n; ++i) {
      log.Insert(changes[static_cast<size_t>(i)]);
      if ((i + 1) % step == 0 || i + 1 == n) {
        const int64_t t = bench::SteadyNowNs();
        p.Extend(log);
        extend_ns += bench::SteadyNowNs() - t;
      }
    }
    benchmark::DoNotOptimize(p.At(n));
  }
  // Only the extensions: the log's inserts are the replica's cost, measured elsewhere.
  state.counters["extend_ns_per_change"] =
      static_cast<double>(extend_ns) / static_cast<double>(state.iterations() * n);
}
BENCHMARK(BM_PrefixHashesGrowing)->Args({100000, 100})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "anti-entropy-bench", "error", false);
}
