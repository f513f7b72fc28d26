// Benchmarks of the protocol engine over real LCM: features/s from node A to node B against raw
// LCM of same-size messages in the same run, authenticated against unauthenticated PDUs in the
// same run, and the latency from create on A to applied on B (authenticated against
// unauthenticated too).
#include <time.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/memory_change_store.h"
#include "pdu/pdu_traits.h"
#include "simulation/bench/latency_stats.h"
#include "simulation/bench/lcm_cluster.h"
#include "transport/bench/bench_main.h"
#include "transport/bench/raw_lcm_link.h"
#include "transport/test/private_netns.h"

namespace dt {
namespace {

constexpr int kBatch = 500;
constexpr const char* kMemq = "memq://";
constexpr const char* kUdpm = "udpm://239.255.76.67:7667?ttl=0";
// The raw baseline gets its own port so its datagrams never queue on the replicas' sockets.
constexpr const char* kUdpmRaw = "udpm://239.255.76.67:7668?ttl=0";
// The authenticated exercise of the auth-vs-plain run: another port again.
constexpr const char* kUdpmAuth = "udpm://239.255.76.67:7669?ttl=0";
const NodeAddress kA{1, 1}, kB{1, 2}, kServer{1, 100};

// Protocol defaults (docs/protocol.md): A may have 256 unacknowledged changes and the server
// acknowledges every 500 ms, so the sustained rate is at most 256 / 0.5 s = 512 features/s.
ReplicaConfig Defaults() { return ReplicaConfig{}; }

using bench::Percentile;

// A server (changes in memory), node A and node B, signed on, and a tap on B's bus that runs
// right after B's replica has handled each Construct: the moment the feature is applied on B.
// With a key every PDU is authenticated (pdu/pdu_auth.h), as in an exercise with [auth].
class ThreeReplicas {
 public:
  ThreeReplicas(const std::string& url, ReplicaConfig rc,
                std::shared_ptr<const ExerciseKey> key = nullptr)
      : cluster_(url, bench::BenchGround(), rc) {
    cluster_.set_key(std::move(key));
    cluster_.Start(kServer, NodeRole::kServer, &store_);
    cluster_.Start(kA, NodeRole::kNode);
    Replica& b = cluster_.Start(kB, NodeRole::kNode);
    cluster_.bus(kB).Subscribe<dtpdu::construct_t>([this, &b](const dtpdu::construct_t& p) {
      if (FromPdu(p.origin) != kA) return;
      const auto n = static_cast<size_t>(p.feature_number);
      if (n >= created_ns_.size() || created_ns_[n] < 0) return;  // not timed, or seen
      if (b.records().Find(FeatureId{kA.site, kA.host, static_cast<uint32_t>(n)}) == nullptr) {
        return;
      }
      latencies_us_.push_back(static_cast<double>(bench::SteadyNowNs() - created_ns_[n]) / 1000.0);
      created_ns_[n] = -1;
      ++applied_on_b_;
    });
    const int64_t deadline = cluster_.now_ms() + 10 * rc.silence_ms + 5000;
    while (!(a().signed_on() && cluster_.at(kB).signed_on()) && cluster_.now_ms() < deadline) {
      cluster_.Pump(1);
    }
  }

  bool ready() { return a().signed_on() && b().signed_on(); }
  Replica& a() { return cluster_.at(kA); }
  Replica& b() { return cluster_.at(kB); }
  bench::LcmCluster& cluster() { return cluster_; }

  // Creates one crater on A, timed from before the call. False if the command was refused.
  bool Create(int64_t n, std::string* error) {
    const int64_t t = bench::SteadyNowNs();
    auto id = a().Create(bench::BenchCrater(n));
    create_ns_ += bench::SteadyNowNs() - t;
    if (!id) {
      *error = id.error().message;
      return false;
    }
    const size_t number = id.value().number;
    if (created_ns_.size() <= number) created_ns_.resize(number + 1, -1);
    created_ns_[number] = t;
    return true;
  }

  int64_t applied_on_b() const { return applied_on_b_; }
  int64_t create_ns() const { return create_ns_; }
  std::vector<double>& latencies_us() { return latencies_us_; }

 private:
  MemoryChangeStore store_;
  bench::LcmCluster cluster_;
  std::vector<int64_t> created_ns_;  // by A's feature number; -1 once applied on B
  std::vector<double> latencies_us_;
  int64_t applied_on_b_ = 0;
  int64_t create_ns_ = 0;  // inside A's Create calls
};

// Pumps until B has applied `target` features or 10 s passed (a loss recovered by playback is
// still counted; one never recovered fails the run).
bool PumpUntilApplied(ThreeReplicas& r, int64_t target) {
  const int64_t deadline = r.cluster().now_ms() + 10000;
  while (r.applied_on_b() < target) {
    if (r.cluster().now_ms() > deadline) return false;
    r.cluster().Pump(1);
  }
  return true;
}

// CPU time of the calling thread, ns: on a shared machine it counts the work done, not the time
// the thread waited for a core.
int64_t ThreadCpuNs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return int64_t{t.tv_sec} * 1000000000 + t.tv_nsec;
}

// Creates kBatch craters on A (numbers from *n on), waiting for acknowledgements whenever A's
// window is full, then pumps until B has applied them all. Returns the wall time in ns, or -1
// with *error set.
int64_t CreateBatch(ThreeReplicas& r, int64_t* n, int64_t* window_waits, std::string* error) {
  const int64_t t = bench::SteadyNowNs();
  const int64_t target = r.applied_on_b() + kBatch;
  for (int created = 0; created < kBatch;) {
    if (r.Create(*n, error)) {
      ++*n;
      ++created;
    } else if (error->find("not acknowledged") != std::string::npos) {
      ++*window_waits;
      r.cluster().Pump(1);
    } else {
      *error = "create refused: " + *error;
      return -1;
    }
  }
  if (!PumpUntilApplied(r, target)) {
    *error = "B did not apply every feature within 10 s";
    return -1;
  }
  return bench::SteadyNowNs() - t;
}

// Per iteration: kBatch raw LCM messages of a Construct's size (lcm_publish, a counting handler),
// then kBatch craters created on A until B has applied them all (A waits for acknowledgements
// whenever its window is full). Time (manual) is the engine's; counters give both rates, their
// ratio and B's create-to-applied latency under this load.
void BM_NodeToNodeVsRawLcm(benchmark::State& state, std::string url, bool fast_acks) {
  if (url != kMemq && dt::testing::NetnsSkipReason()) {
    state.SkipWithError("udpm runs only inside a private network namespace");
    return;
  }
  ThreeReplicas r(url, fast_acks ? bench::FastAckConfig() : Defaults());
  if (!r.ready()) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  // The exact bytes of a Construct as A sends it, for same-size raw messages.
  r.cluster().RecordConstructs(true);
  std::string error;
  if (!r.Create(0, &error) || !PumpUntilApplied(r, 1)) {
    state.SkipWithError(("first crater: " + error).c_str());
    return;
  }
  r.cluster().RecordConstructs(false);
  const auto sample = r.cluster().TakeRecorded();  // memq only
  // A Construct of the same crater encoded here is the same size (every field but the vertex
  // edits has a fixed size); over memq the captured message itself is used.
  const std::vector<uint8_t> bytes =
      sample.empty() ? bench::BenchConstructBytes(kA) : sample.front();
  bench::RawLcmLink raw(url == kMemq ? kMemq : kUdpmRaw, ChannelName(1, PduType::kConstruct));
  r.latencies_us().clear();
  const int64_t create0 = r.create_ns(), a0 = r.cluster().ReceiveNs(kA),
                b0 = r.cluster().ReceiveNs(kB), s0 = r.cluster().ReceiveNs(kServer);

  int64_t raw_ns = 0, engine_ns = 0, raw_lost = 0, window_waits = 0, n = 1;
  for (auto _ : state) {
    const int64_t t = bench::SteadyNowNs();
    raw_lost += raw.Send(bytes, kBatch);
    raw_ns += bench::SteadyNowNs() - t;

    const int64_t dt_ns = CreateBatch(r, &n, &window_waits, &error);
    if (dt_ns < 0) {
      state.SkipWithError(error.c_str());
      return;
    }
    engine_ns += dt_ns;
    state.SetIterationTime(static_cast<double>(dt_ns) / 1e9);
  }
  const double features = static_cast<double>(state.iterations()) * kBatch;
  const double engine_rate = features / (static_cast<double>(engine_ns) / 1e9);
  const double raw_rate = features / (static_cast<double>(raw_ns) / 1e9);
  state.SetItemsProcessed(static_cast<int64_t>(features));
  state.counters["features_per_s"] = engine_rate;
  state.counters["raw_lcm_per_s"] = raw_rate;
  state.counters["ratio"] = engine_rate / raw_rate;
  state.counters["raw_lost"] = static_cast<double>(raw_lost);
  state.counters["bytes"] = static_cast<double>(bytes.size());
  state.counters["window_waits"] = static_cast<double>(window_waits);
  state.counters["lat_p50_us"] = Percentile(r.latencies_us(), 0.50);
  state.counters["lat_p99_us"] = Percentile(r.latencies_us(), 0.99);
  // Where the time goes, per feature (memq: every replica runs on this one thread): A's Create
  // (check, apply, encode, publish), each replica's receive handlers (A's own echo included).
  auto per_feature_us = [&](int64_t ns) { return static_cast<double>(ns) / features / 1000.0; };
  state.counters["raw_us"] = 1e6 / raw_rate;
  state.counters["a_create_us"] = per_feature_us(r.create_ns() - create0);
  state.counters["a_recv_us"] = per_feature_us(r.cluster().ReceiveNs(kA) - a0);
  state.counters["b_recv_us"] = per_feature_us(r.cluster().ReceiveNs(kB) - b0);
  state.counters["server_recv_us"] = per_feature_us(r.cluster().ReceiveNs(kServer) - s0);
  // Zero final loss: B holds every change A made and knows of no gap.
  const bool equal = r.b().caught_up() && r.b().live_feature_count() == r.a().live_feature_count();
  state.counters["final_lost"] =
      static_cast<double>(r.a().live_feature_count() - r.b().live_feature_count());
  if (!equal) state.SkipWithError("B does not hold every feature A created");
}

// The two exercises of an authenticated-against-plain run, signed on; null (and the run skipped,
// saying why) if udpm has no private namespace or A and B did not sign on.
struct PlainAndAuthed {
  PlainAndAuthed(const std::string& plain_url, const std::string& auth_url)
      : plain(plain_url, bench::FastAckConfig()),
        authed(auth_url, bench::FastAckConfig(),
               std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x42))) {}
  static std::unique_ptr<PlainAndAuthed> Make(benchmark::State& state, const std::string& plain_url,
                                              const std::string& auth_url) {
    if (plain_url != kMemq && dt::testing::NetnsSkipReason()) {
      state.SkipWithError("udpm runs only inside a private network namespace");
      return nullptr;
    }
    auto pair = std::make_unique<PlainAndAuthed>(plain_url, auth_url);
    if (!pair->plain.ready() || !pair->authed.ready()) {
      state.SkipWithError("A and B did not sign on");
      return nullptr;
    }
    return pair;
  }
  ThreeReplicas plain;
  ThreeReplicas authed;
};

// Authenticated ÷ unauthenticated, same run, interleaved: two exercises of a server, A and B,
// one with every PDU signed and verified (the exercise key), one without, on separate LCM
// queues (memq) or ports (udpm). Per iteration kBatch craters from A to B in each, the order
// alternating; time (manual) is the sum. Counters give both rates and their ratio, by wall time
// and by this thread's CPU time (everything runs on it: over udpm the system calls too).
void BM_NodeToNodeAuthVsPlain(benchmark::State& state, std::string plain_url,
                              std::string auth_url) {
  auto pair = PlainAndAuthed::Make(state, plain_url, auth_url);
  if (!pair) return;
  ThreeReplicas& plain = pair->plain;
  ThreeReplicas& authed = pair->authed;
  std::string error;
  int64_t n_plain = 0, n_auth = 0, waits = 0, plain_ns = 0, auth_ns = 0, i = 0;
  int64_t plain_cpu = 0, auth_cpu = 0;
  // Warm-up: a first batch in each, so both have every peer's reports again.
  if (CreateBatch(plain, &n_plain, &waits, &error) < 0 ||
      CreateBatch(authed, &n_auth, &waits, &error) < 0) {
    state.SkipWithError(("warm-up: " + error).c_str());
    return;
  }
  for (auto _ : state) {
    int64_t p = 0, a = 0;
    auto timed = [&](ThreeReplicas& r, int64_t* n, int64_t* cpu) {
      const int64_t c = ThreadCpuNs();
      const int64_t wall = CreateBatch(r, n, &waits, &error);
      *cpu += ThreadCpuNs() - c;
      return wall;
    };
    if (i++ % 2 == 0) {
      p = timed(plain, &n_plain, &plain_cpu);
      a = p < 0 ? -1 : timed(authed, &n_auth, &auth_cpu);
    } else {
      a = timed(authed, &n_auth, &auth_cpu);
      p = a < 0 ? -1 : timed(plain, &n_plain, &plain_cpu);
    }
    if (p < 0 || a < 0) {
      state.SkipWithError(error.c_str());
      return;
    }
    plain_ns += p;
    auth_ns += a;
    state.SetIterationTime(static_cast<double>(p + a) / 1e9);
  }
  bench::ReportAuthThroughputRatios(state, static_cast<double>(state.iterations()) * kBatch,
                                    plain_ns, auth_ns, plain_cpu, auth_cpu);
  state.counters["window_waits"] = static_cast<double>(waits);
  const PduBus& b = authed.cluster().bus(kB);
  state.counters["auth_rejected"] = static_cast<double>(b.rejects().total());
  const bool equal = plain.b().caught_up() && authed.b().caught_up() &&
                     plain.b().live_feature_count() == plain.a().live_feature_count() &&
                     authed.b().live_feature_count() == authed.a().live_feature_count();
  if (!equal) state.SkipWithError("B does not hold every feature A created");
  if (b.authenticator() == nullptr || b.rejects().total() != 0) {
    state.SkipWithError("the authenticated exercise is not authenticating, or rejected PDUs");
  }
}

// One crater at a time on an otherwise idle exercise: create on A, then pump until B has applied
// it. Iterations are features; the counters are percentiles of create-to-applied time.
void BM_CreateToAppliedLatency(benchmark::State& state, std::string url) {
  if (url != kMemq && dt::testing::NetnsSkipReason()) {
    state.SkipWithError("udpm runs only inside a private network namespace");
    return;
  }
  ThreeReplicas r(url, bench::FastAckConfig());
  if (!r.ready()) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  std::string error;
  int64_t n = 0;
  for (auto _ : state) {
    const int64_t t = bench::SteadyNowNs();
    while (!r.Create(n, &error)) r.cluster().Pump(1);  // a full window: wait for the server
    ++n;
    const int64_t target = r.applied_on_b() + 1;
    while (r.applied_on_b() < target) r.cluster().Pump(0);
    state.SetIterationTime(static_cast<double>(bench::SteadyNowNs() - t) / 1e9);
  }
  state.counters["lat_p50_us"] = Percentile(r.latencies_us(), 0.50);
  state.counters["lat_p99_us"] = Percentile(r.latencies_us(), 0.99);
  state.counters["lat_max_us"] = Percentile(r.latencies_us(), 1.0);
}

// Latency authenticated against unauthenticated, same run, interleaved: the two exercises of
// BM_NodeToNodeAuthVsPlain; per iteration one crater from A to B in each, the order alternating,
// each on an otherwise idle exercise as in BM_CreateToAppliedLatency. Counters: percentiles of
// each, and plain ÷ authenticated of the medians and 99th percentiles.
void BM_LatencyAuthVsPlain(benchmark::State& state, std::string plain_url, std::string auth_url) {
  auto pair = PlainAndAuthed::Make(state, plain_url, auth_url);
  if (!pair) return;
  ThreeReplicas& plain = pair->plain;
  ThreeReplicas& authed = pair->authed;
  std::string error;
  int64_t n_plain = 0, n_auth = 0, i = 0;
  auto one = [&](ThreeReplicas& r, int64_t* n) {
    const int64_t t = bench::SteadyNowNs();
    while (!r.Create(*n, &error)) r.cluster().Pump(1);  // a full window: wait for the server
    ++*n;
    const int64_t target = r.applied_on_b() + 1;
    while (r.applied_on_b() < target) r.cluster().Pump(0);
    return bench::SteadyNowNs() - t;
  };
  for (auto _ : state) {
    int64_t ns = 0;
    if (i++ % 2 == 0) {
      ns = one(plain, &n_plain) + one(authed, &n_auth);
    } else {
      ns = one(authed, &n_auth) + one(plain, &n_plain);
    }
    state.SetIterationTime(static_cast<double>(ns) / 1e9);
  }
  bench::ReportAuthLatencyRatios(state, plain.latencies_us(), authed.latencies_us());
  const PduBus& b = authed.cluster().bus(kB);
  if (b.authenticator() == nullptr || b.rejects().total() != 0) {
    state.SkipWithError("the authenticated exercise is not authenticating, or rejected PDUs");
  }
}

// Fixed iterations: each run signs on once (2 s of silence with the defaults).
BENCHMARK_CAPTURE(BM_NodeToNodeVsRawLcm, memq_fast_acks, std::string(kMemq), true)
    ->UseManualTime()
    ->Iterations(400)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_NodeToNodeVsRawLcm, memq_defaults, std::string(kMemq), false)
    ->UseManualTime()
    ->Iterations(6)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_NodeToNodeVsRawLcm, udpm_fast_acks, std::string(kUdpm), true)
    ->UseManualTime()
    ->Iterations(100)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_NodeToNodeAuthVsPlain, memq, std::string(kMemq), std::string(kMemq))
    ->UseManualTime()
    ->Iterations(200)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_NodeToNodeAuthVsPlain, udpm, std::string(kUdpm), std::string(kUdpmAuth))
    ->UseManualTime()
    ->Iterations(60)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LatencyAuthVsPlain, memq, std::string(kMemq), std::string(kMemq))
    ->UseManualTime()
    ->Iterations(5000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CreateToAppliedLatency, memq, std::string(kMemq))
    ->UseManualTime()
    ->Iterations(5000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CreateToAppliedLatency, udpm, std::string(kUdpm))
    ->UseManualTime()
    ->Iterations(5000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "protocol-bench", "error", true,
                                  "the udpm runs are skipped");
}
