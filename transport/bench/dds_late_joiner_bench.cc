// A late joiner's catch-up over DDS: N features' latest changes from a durable (transient-local)
// writer's history, against the same N sent again once the joiner is matched, which is the least
// a playback costs on the wire (one PDU per change; the protocol adds requests, windows and the
// replicas' work). The holder and the joiner are in one process but in DDS domains 1 and 2, both
// mapped onto domain 0 on the network (cyclonedds-two-domains.xml), so every sample crosses
// loopback as between two processes.
#include <chrono>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "pdu/test/sample_pdus.h"
#include "transport/bench/bench_main.h"
#include "transport/dds_transport.h"
#include "transport/retrying_transport.h"

namespace dt {
namespace {

const std::string kConfig =
    std::string(DT_SOURCE_DIR) + "/transport/bench/cyclonedds-two-domains.xml";
constexpr uint8_t kExercise = sample::kSampleExercise;

std::unique_ptr<DdsTransport> Make(uint32_t domain, bool durable) {
  DdsConfig c;
  c.domain_id = domain;
  c.config_file = kConfig;
  c.durable_features = durable;
  return std::make_unique<DdsTransport>(c, kExercise);
}

std::vector<uint8_t> FeatureUpdate(int64_t feature) {
  auto pdu = sample::Update();
  pdu.feature_number = feature;
  return EncodePdu(pdu);
}

// Handles `joiner` (and `holder`, to move its retries) until `received` reaches n or 60 s pass.
bool Drain(Transport& joiner, Transport* holder, const int64_t& received, int64_t n) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (received < n && std::chrono::steady_clock::now() < end) {
    if (holder != nullptr && !holder->HandleTimeout(0).ok()) return false;
    if (!joiner.HandleTimeout(5).ok()) return false;
  }
  return received == n;
}

// Per iteration: a new joiner (domain, participant, reader) until it holds all N features from
// the holder's transient-local history.
void BM_LateJoinerFromDurability(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("DDS runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t n = state.range(0);
  auto holder = Make(1, true);
  for (int64_t f = 1; f <= n; ++f) {
    // No reader yet: nothing waits for acknowledgements, so no write is refused.
    if (!holder->Publish(PduType::kUpdate, FeatureUpdate(f)).ok()) {
      state.SkipWithError("the holder's write failed");
      return;
    }
  }
  for (auto _ : state) {
    int64_t received = 0;
    auto joiner = Make(2, true);
    joiner->Subscribe(PduType::kUpdate, [&](std::span<const uint8_t>) { ++received; });
    if (!Drain(*joiner, nullptr, received, n)) {
      state.SkipWithError("the joiner did not get every feature within 60 s");
      return;
    }
    state.PauseTiming();
    joiner.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Per iteration: a new joiner; once the holder sees it matched, the holder sends all N features
// again (through RetryingTransport, as every process does) until the joiner holds them.
void BM_LateJoinerByResending(benchmark::State& state) {
  if (auto reason = testing::NetnsSkipReason()) {
    state.SkipWithError(("DDS runs only in a private network namespace: " + *reason).c_str());
    return;
  }
  const int64_t n = state.range(0);
  auto dds = Make(1, false);
  DdsTransport* holder_dds = dds.get();
  RetryingTransport holder(std::move(dds));
  std::vector<std::vector<uint8_t>> updates;
  for (int64_t f = 1; f <= n; ++f) updates.push_back(FeatureUpdate(f));
  for (auto _ : state) {
    int64_t received = 0;
    auto joiner = Make(2, false);
    joiner->Subscribe(PduType::kUpdate, [&](std::span<const uint8_t>) { ++received; });
    if (!holder_dds->WaitForReaders(PduType::kUpdate, 1, 60000)) {
      state.SkipWithError("the joiner's reader was never matched");
      return;
    }
    for (const auto& u : updates) {
      if (!holder.Publish(PduType::kUpdate, u).ok()) {
        state.SkipWithError("the holder's retry queue refused a write");
        return;
      }
    }
    if (!Drain(*joiner, &holder, received, n)) {
      state.SkipWithError("the joiner did not get every feature within 60 s");
      return;
    }
    state.PauseTiming();
    joiner.reset();
    // The joiner's reader must be unmatched before the next one is counted.
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while ((holder.queued() > 0 || holder_dds->MatchedReaders(PduType::kUpdate) != 0) &&
           std::chrono::steady_clock::now() < end) {
      (void)holder.HandleTimeout(5);
    }
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["retried"] = static_cast<double>(holder.counters().retried);
}

BENCHMARK(BM_LateJoinerFromDurability)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_LateJoinerByResending)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "dds-late-joiner-bench", "warn", true,
                                  "every case is skipped");
}
