// The protocol benchmarks with every replica on its own thread and its own udpm socket, as an
// exercise runs them (one process per node): node A to node B throughput and a rejoin catch-up,
// each against raw LCM over udpm with the receiver on its own thread, in the same run; and node
// A to node B throughput and latency authenticated against unauthenticated, and the latency of a
// single change batched against unbatched.
#include <algorithm>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "engine/memory_change_store.h"
#include "simulation/bench/latency_stats.h"
#include "simulation/bench/lcm_cluster.h"
#include "simulation/bench/replica_thread.h"
#include "transport/bench/bench_main.h"
#include "transport/bench/raw_lcm_link.h"
#include "transport/test/private_netns.h"

namespace dt {
namespace {

using bench::ReplicaThread;
using bench::SteadyNowNs;

constexpr const char* kUdpm = "udpm://239.255.76.67:7667?ttl=0";
// The raw baselines' own ports: their datagrams never queue on the replicas' sockets or on each
// other's.
constexpr const char* kUdpmRaw = "udpm://239.255.76.67:7668?ttl=0";
constexpr const char* kUdpmRawGroup = "udpm://239.255.76.67:7669?ttl=0";
// The authenticated exercise of the auth-vs-plain run.
constexpr const char* kUdpmAuth = "udpm://239.255.76.67:7670?ttl=0";
// The unbatched exercise of the batched-vs-single latency run.
constexpr const char* kUdpmSingle = "udpm://239.255.76.67:7671?ttl=0";
const NodeAddress kA{1, 1}, kB{1, 2}, kServer{1, 100};
constexpr int kBurst = 500;
constexpr size_t kRawWindow = 256;  // the raw rejoin baseline's batch: the playback window

// Every replica here stands on BenchGround, whose digest is computed once, as a ground cache's
// header gives it to a process (terrain/ground_cache.h): a restart builds its ground but does not
// digest it again.
ReplicaConfig Config(ReplicaConfig base, NodeAddress address, NodeRole role) {
  static const TerrainDigest kGroundDigest = ComputeDigest(bench::BenchGround());
  base.address = address;
  base.role = role;
  base.ground_digest = kGroundDigest;
  return base;
}

std::unique_ptr<ReplicaThread> Start(const ReplicaConfig& base, NodeAddress address, NodeRole role,
                                     ChangeStore* store, int64_t epoch_ns) {
  return std::make_unique<ReplicaThread>(kUdpm, bench::BenchGround(), Config(base, address, role),
                                         store, epoch_ns);
}

// Waits for a step's future; false after timeout_s.
bool WaitFor(std::future<int64_t>& done, int timeout_s) {
  return done.wait_for(std::chrono::seconds(timeout_s)) == std::future_status::ready;
}

// A step creating craters first..first+count-1; a full window (the server has not acknowledged
// yet) returns to the loop, which dispatches the acknowledgement.
ReplicaThread::Step CreateCraters(int64_t first, int64_t count, std::string* error) {
  auto next = std::make_shared<int64_t>(first);
  return [next, end = first + count, error](Replica& r) {
    while (*next < end) {
      auto id = r.Create(bench::BenchCrater(*next));
      if (!id) {
        if (id.error().message.find("not acknowledged") == std::string::npos) {
          *error = id.error().message;
          return true;  // refused for another reason: stop, the caller reports it
        }
        return false;
      }
      ++*next;
    }
    return true;
  };
}

std::vector<std::vector<uint8_t>> Copies(const std::vector<uint8_t>& bytes, size_t n) {
  return std::vector<std::vector<uint8_t>>(n, bytes);
}

// Per iteration: range(0) (the burst) raw messages of a Construct's size from this thread to one
// receiver thread, the same to three, then as many craters created on A's thread until B's thread
// has applied them all (the server's thread stores and acknowledges them meanwhile). Wall time
// (manual) is the engine's.
void BM_NodeToNodeThreads(benchmark::State& state) {
  const auto burst = static_cast<int>(state.range(0));
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("udpm runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t epoch = SteadyNowNs();
  const ReplicaConfig rc = bench::FastAckConfig();
  // Before the threads: a step that outlives a timed-out wait may still write it.
  std::string error;
  MemoryChangeStore store;
  auto server = Start(rc, kServer, NodeRole::kServer, &store, epoch);
  auto a = Start(rc, kA, NodeRole::kNode, nullptr, epoch);
  auto b = Start(rc, kB, NodeRole::kNode, nullptr, epoch);
  auto a_on = a->Post([](Replica& r) { return r.signed_on(); });
  auto b_on = b->Post([](Replica& r) { return r.signed_on(); });
  if (!WaitFor(a_on, 20) || !WaitFor(b_on, 20)) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  // One receiver (the raw LCM), and three: every message of A's reaches A's own socket,
  // B's and the server's, so raw LCM with the same deliveries.
  bench::ThreadedRawLcmLink raw(kUdpmRaw, ChannelName(1, PduType::kConstruct));
  bench::ThreadedRawLcmLink raw_group(kUdpmRawGroup, ChannelName(1, PduType::kConstruct), 3);
  const auto messages = Copies(bench::BenchConstructBytes(kA), burst);

  int64_t raw_ns = 0, group_ns = 0, engine_ns = 0, raw_lost = 0, n = 0, a_done_ns = 0;
  const int64_t cpu0_a = a->CpuNs(), cpu0_b = b->CpuNs(), cpu0_s = server->CpuNs();
  const uint64_t batches0_a = a->BatchesSent();
  int64_t raw_cpu_ns = 0, engine_cpu_ns = 0;
  auto process_cpu_ns = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return int64_t{ts.tv_sec} * 1000000000 + ts.tv_nsec;
  };
  for (auto _ : state) {
    int64_t c = process_cpu_ns();
    int64_t t = SteadyNowNs();
    raw_lost += raw.Transfer(messages, burst);
    raw_ns += SteadyNowNs() - t;
    raw_cpu_ns += process_cpu_ns() - c;
    t = SteadyNowNs();
    raw_lost += raw_group.Transfer(messages, burst);
    group_ns += SteadyNowNs() - t;

    const auto target = static_cast<size_t>(n + burst);
    c = process_cpu_ns();
    t = SteadyNowNs();
    auto created = a->Post(CreateCraters(n, burst, &error));
    auto applied = b->Post([target](Replica& r) { return r.live_feature_count() >= target; });
    // B's applying first: waiting for A's creations woke this thread in mid-burst, to take a
    // core from B and the server while they applied (the raw baselines wait once, for the end).
    const bool all_applied = WaitFor(applied, 10);
    if (!WaitFor(created, 10)) {
      state.SkipWithError("A did not create its burst within 10 s");
      return;
    }
    if (!error.empty()) {  // written on A's thread before `created` became ready
      state.SkipWithError(("A's create refused: " + error).c_str());
      return;
    }
    if (!all_applied) {
      state.SkipWithError("B did not apply every feature within 10 s");
      return;
    }
    const int64_t dt_ns = applied.get() - t;
    a_done_ns += created.get() - t;
    // Untimed: the server holds the burst too before the raw baselines run again, so they never
    // share the cores with the engine's leftover work (whose CPU is counted as the engine's).
    auto stored = server->Post([target](Replica& r) { return r.live_feature_count() >= target; });
    if (!WaitFor(stored, 10)) {
      state.SkipWithError("the server did not hold every feature within 10 s");
      return;
    }
    engine_cpu_ns += process_cpu_ns() - c;
    n += burst;
    engine_ns += dt_ns;
    state.SetIterationTime(static_cast<double>(dt_ns) / 1e9);
  }
  const double features = static_cast<double>(n);
  const double engine_rate = features / (static_cast<double>(engine_ns) / 1e9);
  const double raw_rate = features / (static_cast<double>(raw_ns) / 1e9);
  const double group_rate = features / (static_cast<double>(group_ns) / 1e9);
  state.SetItemsProcessed(n);
  state.counters["features_per_s"] = engine_rate;
  state.counters["raw_lcm_per_s"] = raw_rate;
  state.counters["ratio"] = engine_rate / raw_rate;
  state.counters["raw3_lcm_per_s"] = group_rate;
  state.counters["ratio3"] = engine_rate / group_rate;
  state.counters["raw_lost"] = static_cast<double>(raw_lost);
  // Where the time goes, in CPU rather than wall time (what the two cores allow): the process's
  // CPU per message of the raw one-receiver baseline (sender, LCM's reader thread, receiver) and
  // per feature of the engine (three replicas and their readers); A's creations of a burst
  // against the whole; each replica thread's CPU per feature (not its socket's reader).
  state.counters["raw_cpu_us"] = static_cast<double>(raw_cpu_ns) / 1e3 / features;
  state.counters["engine_cpu_us"] = static_cast<double>(engine_cpu_ns) / 1e3 / features;
  state.counters["a_created_share"] =
      static_cast<double>(a_done_ns) / static_cast<double>(engine_ns);
  state.counters["cpu_us_a"] = static_cast<double>(a->CpuNs() - cpu0_a) / 1e3 / features;
  state.counters["cpu_us_b"] = static_cast<double>(b->CpuNs() - cpu0_b) / 1e3 / features;
  state.counters["cpu_us_server"] = static_cast<double>(server->CpuNs() - cpu0_s) / 1e3 / features;
  // Features per datagram A sent (its lone PDUs, reports among them, not counted).
  state.counters["a_features_per_batch"] =
      features / static_cast<double>(std::max<uint64_t>(1, a->BatchesSent() - batches0_a));
  // Zero final loss: B holds every feature A created and knows of no gap.
  size_t a_live = 0, b_live = 0;
  bool b_caught_up = false;
  a->Run([&](Replica& r) { a_live = r.live_feature_count(); });
  b->Run([&](Replica& r) {
    b_live = r.live_feature_count();
    b_caught_up = r.caught_up();
  });
  state.counters["final_lost"] = static_cast<double>(a_live) - static_cast<double>(b_live);
  if (!b_caught_up || a_live != b_live) state.SkipWithError("B does not hold every feature");
}

// A server, A and B, each on its own thread and udpm socket, signed on; with a key, every PDU
// authenticated.
struct ThreadedExercise {
  ThreadedExercise(const std::string& url, const ReplicaConfig& rc, int64_t epoch,
                   std::shared_ptr<const ExerciseKey> key, bool batch = true) {
    auto start = [&](NodeAddress address, NodeRole role, ChangeStore* s) {
      return std::make_unique<ReplicaThread>(url, bench::BenchGround(), Config(rc, address, role),
                                             s, epoch, key, batch);
    };
    server = start(kServer, NodeRole::kServer, &store);
    a = start(kA, NodeRole::kNode, nullptr);
    b = start(kB, NodeRole::kNode, nullptr);
  }
  bool SignOn() {
    auto a_on = a->Post([](Replica& r) { return r.signed_on(); });
    auto b_on = b->Post([](Replica& r) { return r.signed_on(); });
    return WaitFor(a_on, 20) && WaitFor(b_on, 20);
  }
  // `count` craters created on A's thread until B's thread has applied them all: wall ns, or -1
  // with *error set.
  int64_t Burst(std::string* error, int64_t count = kBurst) {
    const auto target = static_cast<size_t>(n + count);
    const int64_t t = SteadyNowNs();
    auto created = a->Post(CreateCraters(n, count, error));
    auto applied = b->Post([target](Replica& r) { return r.live_feature_count() >= target; });
    if (!WaitFor(created, 10)) {
      *error = "A did not create its burst within 10 s";
      return -1;
    }
    if (!error->empty()) return -1;  // written on A's thread before `created` became ready
    if (!WaitFor(applied, 10)) {
      *error = "B did not apply every feature within 10 s";
      return -1;
    }
    n += count;
    return applied.get() - t;
  }
  // CPU time of the three replicas' threads so far.
  int64_t CpuNs() { return server->CpuNs() + a->CpuNs() + b->CpuNs(); }
  bool Complete() {
    size_t a_live = 0, b_live = 0;
    bool b_caught_up = false;
    a->Run([&](Replica& r) { a_live = r.live_feature_count(); });
    b->Run([&](Replica& r) {
      b_live = r.live_feature_count();
      b_caught_up = r.caught_up();
    });
    return b_caught_up && a_live == b_live;
  }

  MemoryChangeStore store;
  std::unique_ptr<ReplicaThread> server, a, b;  // after the store they use
  int64_t n = 0;
};

// Authenticated ÷ unauthenticated with one thread per replica, same run, interleaved: two
// exercises (server, A, B) on separate ports, one with every PDU signed and verified. Per
// iteration a burst of kBurst craters from A to B in each, the order alternating; time (manual)
// is the sum; counters give both rates and their ratio, by wall time and by the CPU time the
// three replica threads used (robust to other load on the machine).
void BM_NodeToNodeThreadsAuthVsPlain(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("udpm runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t epoch = SteadyNowNs();
  const ReplicaConfig rc = bench::FastAckConfig();
  std::string error;  // before the threads: a step that outlives a timed-out wait may write it
  ThreadedExercise plain(kUdpm, rc, epoch, nullptr);
  ThreadedExercise authed(kUdpmAuth, rc, epoch,
                          std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x42)));
  if (!plain.SignOn() || !authed.SignOn()) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  if (plain.Burst(&error) < 0 || authed.Burst(&error) < 0) {  // warm-up
    state.SkipWithError(("warm-up: " + error).c_str());
    return;
  }
  int64_t plain_ns = 0, auth_ns = 0, plain_cpu = 0, auth_cpu = 0, i = 0;
  auto burst = [&](ThreadedExercise& ex, int64_t* cpu) {
    const int64_t c = ex.CpuNs();
    const int64_t wall = ex.Burst(&error);
    *cpu += ex.CpuNs() - c;
    return wall;
  };
  for (auto _ : state) {
    int64_t p = 0, a = 0;
    if (i++ % 2 == 0) {
      p = burst(plain, &plain_cpu);
      a = p < 0 ? -1 : burst(authed, &auth_cpu);
    } else {
      a = burst(authed, &auth_cpu);
      p = a < 0 ? -1 : burst(plain, &plain_cpu);
    }
    if (p < 0 || a < 0) {
      state.SkipWithError(error.c_str());
      return;
    }
    plain_ns += p;
    auth_ns += a;
    state.SetIterationTime(static_cast<double>(p + a) / 1e9);
  }
  bench::ReportAuthThroughputRatios(state, static_cast<double>(state.iterations()) * kBurst,
                                    plain_ns, auth_ns, plain_cpu, auth_cpu);
  if (!plain.Complete() || !authed.Complete()) state.SkipWithError("B does not hold every feature");
}

// Per iteration one crater from A to B in each of x and y (which goes first alternating), timed
// from before it is handed to A's thread until B's thread has applied it, in microseconds. False
// (the benchmark skipped with the error) when either fails; `error` is the caller's, declared
// before the threads.
bool TimeSingleChanges(benchmark::State& state, ThreadedExercise& x, ThreadedExercise& y,
                       std::string* error, std::vector<double>* x_us, std::vector<double>* y_us) {
  int64_t i = 0;
  for (auto _ : state) {
    int64_t tx = 0, ty = 0;
    if (i++ % 2 == 0) {
      tx = x.Burst(error, 1);
      ty = tx < 0 ? -1 : y.Burst(error, 1);
    } else {
      ty = y.Burst(error, 1);
      tx = ty < 0 ? -1 : x.Burst(error, 1);
    }
    if (tx < 0 || ty < 0) {
      state.SkipWithError(error->c_str());
      return false;
    }
    x_us->push_back(static_cast<double>(tx) / 1000.0);
    y_us->push_back(static_cast<double>(ty) / 1000.0);
    state.SetIterationTime(static_cast<double>(tx + ty) / 1e9);
  }
  return true;
}

// Latency authenticated against unauthenticated with one thread per replica, same run,
// interleaved: the two exercises above; per iteration one crater from A to B in each (the order
// alternating), timed from before it is handed to A's thread until B's thread has applied it.
// Counters: percentiles of each, and plain ÷ authenticated of the medians and of the 99th
// percentiles (1: the MAC adds nothing).
void BM_LatencyThreadsAuthVsPlain(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("udpm runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t epoch = SteadyNowNs();
  const ReplicaConfig rc = bench::FastAckConfig();
  std::string error;  // before the threads, as above
  ThreadedExercise plain(kUdpm, rc, epoch, nullptr);
  ThreadedExercise authed(kUdpmAuth, rc, epoch,
                          std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x42)));
  if (!plain.SignOn() || !authed.SignOn()) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  std::vector<double> plain_us, auth_us;
  if (!TimeSingleChanges(state, plain, authed, &error, &plain_us, &auth_us)) return;
  bench::ReportAuthLatencyRatios(state, plain_us, auth_us);
  if (!plain.Complete() || !authed.Complete()) state.SkipWithError("B does not hold every feature");
}

// Latency of a single change with batching (PduBus::Batch over each round) ÷ without (every PDU
// alone, as before batches), one thread per replica, same run, interleaved as above. Counters:
// percentiles of each, and single ÷ batched of the medians and 99th percentiles (1: batching
// costs a lone change nothing; the goal is batched ÷ single <= 1.05, so these >= 0.95).
void BM_LatencyThreadsBatchedVsSingle(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("udpm runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t epoch = SteadyNowNs();
  const ReplicaConfig rc = bench::FastAckConfig();
  std::string error;  // before the threads, as above
  ThreadedExercise single(kUdpmSingle, rc, epoch, nullptr, /*batch=*/false);
  ThreadedExercise batched(kUdpm, rc, epoch, nullptr, /*batch=*/true);
  if (!single.SignOn() || !batched.SignOn()) {
    state.SkipWithError("A and B did not sign on");
    return;
  }
  std::vector<double> single_us, batched_us;
  if (!TimeSingleChanges(state, single, batched, &error, &single_us, &batched_us)) return;
  const double s50 = bench::Percentile(single_us, 0.50), b50 = bench::Percentile(batched_us, 0.50);
  const double s99 = bench::Percentile(single_us, 0.99), b99 = bench::Percentile(batched_us, 0.99);
  state.counters["single_p50_us"] = s50;
  state.counters["batched_p50_us"] = b50;
  state.counters["single_p99_us"] = s99;
  state.counters["batched_p99_us"] = b99;
  state.counters["after_over_before_p50"] = b50 / s50;
  state.counters["after_over_before_p99"] = b99 / s99;
  if (!single.Complete() || !batched.Complete()) {
    state.SkipWithError("B does not hold every feature");
  }
}

// range(0) features; range(1) = 0: origin A alive (asked first), 1: A gone, the server answers.
// Protocol defaults (playback window 256) but for A's window of unacknowledged changes, raised
// so the setup is quick. Setup (not timed): server, A and B sign on, B crashes, A creates the
// features and the server stores them. Timed: from B's restart with no state until B holds all
// of A's changes. Then as many Construct-sized messages go from this thread to one raw receiver
// thread in batches of 256 (the window): ratio = catch-up time / raw time; and to as many
// receivers as the playback reaches (the answerer's own socket, B's, and the server's when A
// answers): ratio_same = catch-up time / that raw time.
void BM_RejoinThreads(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("udpm runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t n = state.range(0);
  const bool from_server = state.range(1) == 1;
  const ReplicaConfig defaults;
  ReplicaConfig origin = defaults;
  origin.playback_window = static_cast<int>(kMaxPlaybackSpan);
  double catch_up_s = 0, raw_s = 0, same_s = 0, raw_lost = 0;
  for (auto _ : state) {
    const int64_t epoch = SteadyNowNs();
    std::string error;  // before the threads, as above
    MemoryChangeStore store;
    auto server = Start(defaults, kServer, NodeRole::kServer, &store, epoch);
    auto a = Start(origin, kA, NodeRole::kNode, nullptr, epoch);
    auto b = Start(defaults, kB, NodeRole::kNode, nullptr, epoch);
    auto a_on = a->Post([](Replica& r) { return r.signed_on(); });
    auto b_on = b->Post([](Replica& r) { return r.signed_on(); });
    if (!WaitFor(a_on, 20) || !WaitFor(b_on, 20)) {
      state.SkipWithError("A and B did not sign on");
      return;
    }
    b.reset();  // B crashes
    auto created = a->Post(CreateCraters(0, n, &error));
    auto stored = server->Post([n](Replica& r) {
      const auto d = r.durable_change_seq();
      return d.count(kA) != 0 && d.at(kA) >= n;
    });
    if (!WaitFor(created, 60)) {
      state.SkipWithError("A did not create the features within 60 s");
      return;
    }
    if (!error.empty()) {  // written on A's thread before `created` became ready
      state.SkipWithError(("A's create refused: " + error).c_str());
      return;
    }
    if (!WaitFor(stored, 60)) {
      state.SkipWithError("the server did not store every change within 60 s");
      return;
    }
    if (from_server) a.reset();

    const int64_t t0 = SteadyNowNs();
    b = Start(defaults, kB, NodeRole::kNode, nullptr, epoch);
    auto caught_up = b->Post([n](Replica& r) {
      const ChangeLog* log = r.log(kA);
      return log != nullptr && log->contiguous() >= n;
    });
    if (!WaitFor(caught_up, 120)) {
      state.SkipWithError("B did not catch up within 120 s");
      return;
    }
    const int64_t catch_up_ns = caught_up.get() - t0;

    // The raw link is made after the replicas are gone, so only its two threads run.
    b.reset();
    a.reset();
    server.reset();
    const auto messages = Copies(bench::BenchConstructBytes(kA), static_cast<size_t>(n));
    int64_t raw_ns = 0;
    {
      bench::ThreadedRawLcmLink raw(kUdpmRaw, ChannelName(1, PduType::kConstruct));
      const int64_t t1 = SteadyNowNs();
      raw_lost += static_cast<double>(raw.Transfer(messages, kRawWindow));
      raw_ns = SteadyNowNs() - t1;
    }
    {
      bench::ThreadedRawLcmLink same(kUdpmRawGroup, ChannelName(1, PduType::kConstruct),
                                     from_server ? 2 : 3);
      const int64_t t1 = SteadyNowNs();
      raw_lost += static_cast<double>(same.Transfer(messages, kRawWindow));
      same_s += static_cast<double>(SteadyNowNs() - t1) / 1e9;
    }

    state.SetIterationTime(static_cast<double>(catch_up_ns) / 1e9);
    catch_up_s += static_cast<double>(catch_up_ns) / 1e9;
    raw_s += static_cast<double>(raw_ns) / 1e9;
  }
  const auto iterations = static_cast<double>(state.iterations());
  state.counters["catch_up_ms"] = catch_up_s / iterations * 1000.0;
  state.counters["raw_ms"] = raw_s / iterations * 1000.0;
  state.counters["ratio"] = catch_up_s / raw_s;
  state.counters["raw_same_ms"] = same_s / iterations * 1000.0;
  state.counters["ratio_same"] = catch_up_s / same_s;
  state.counters["raw_lost"] = raw_lost;
  state.counters["features_per_s"] = static_cast<double>(n) / (catch_up_s / iterations);
}

BENCHMARK(BM_NodeToNodeThreads)
    ->ArgName("burst")
    ->Arg(500)
    ->Arg(100)
    ->UseManualTime()
    ->Iterations(200)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LatencyThreadsBatchedVsSingle)
    ->UseManualTime()
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NodeToNodeThreadsAuthVsPlain)
    ->UseManualTime()
    ->Iterations(100)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LatencyThreadsAuthVsPlain)
    ->UseManualTime()
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RejoinThreads)
    ->ArgNames({"features", "from_server"})
    ->Args({10000, 0})
    ->Args({10000, 1})
    ->UseManualTime()
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RejoinThreads)
    ->ArgNames({"features", "from_server"})
    ->Args({100000, 0})
    ->Args({100000, 1})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "threads-bench", "error", true,
                                  "every run is skipped");
}
