// PDU benchmarks: encode, decode+validate, member deltas, sign and verify time per PDU, and PDUs/s
// through PduBus (with and without authentication) over memq, udpm and DDS against raw LCM
// publish/receive of same-size messages in the same run.
// Runs inside a private network namespace it makes itself, like the network tests.
#include <chrono>

#include <benchmark/benchmark.h>
#include <lcm/lcm.h>

#include "pdu/member_delta.h"
#include "pdu/test/sample_pdus.h"
#include "transport/bench/bench_main.h"
#include "transport/bench/raw_lcm_link.h"
#include "transport/dds_transport.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"
#include "transport/test/private_netns.h"

namespace dt {
namespace {

constexpr int kBatch = 500;
constexpr const char* kUdpm = "udpm://239.255.76.67:7667?ttl=0";

template <typename Pdu>
void BM_Encode(benchmark::State& state, Pdu pdu) {
  for (auto _ : state) benchmark::DoNotOptimize(EncodePdu(pdu));
  state.SetItemsProcessed(state.iterations());
}

template <typename Pdu>
void BM_DecodeValidate(benchmark::State& state, Pdu pdu) {
  const auto bytes = EncodePdu(pdu);
  const auto ctx = sample::Context();
  for (auto _ : state) {
    Pdu out;
    auto r = DecodeAndValidate(std::span<const uint8_t>(bytes), ctx, out);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes"] = static_cast<double>(bytes.size());
}

std::shared_ptr<const ExerciseKey> BenchKey() {
  return std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x42));
}

// Appends the authentication trailer (sequence, wall-clock time, keyed BLAKE2b-256) to the
// encoded PDU, as PduBus::Publish does after encoding.
template <typename Pdu>
void BM_Sign(benchmark::State& state, Pdu pdu) {
  PduAuthenticator signer({1, 2}, PduAuthConfig{.key = BenchKey()});
  const auto encoded = EncodePdu(pdu);
  std::vector<uint8_t> bytes;
  bytes.reserve(encoded.size() + kAuthTrailerBytes);
  for (auto _ : state) {
    bytes.assign(encoded.begin(), encoded.end());
    signer.Sign(bytes);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes"] = static_cast<double>(encoded.size() + kAuthTrailerBytes);
}

// Verifies one received signed PDU (trailer, MAC, sender, clock, replay window), as PduBus
// does before decoding. Every PDU carries a new sequence (a replay would be refused), so a
// batch is signed ahead; a fresh receiver per batch is made outside the timing.
template <typename Pdu>
void BM_Verify(benchmark::State& state, Pdu pdu) {
  constexpr size_t kSigned = 4096;
  PduAuthenticator signer({1, 2}, PduAuthConfig{.key = BenchKey()});
  std::vector<std::vector<uint8_t>> batch(kSigned);
  for (auto& b : batch) {
    b = EncodePdu(pdu);
    signer.Sign(b);
  }
  auto receiver =
      std::make_unique<PduAuthenticator>(NodeAddress{2, 2}, PduAuthConfig{.key = BenchKey()});
  size_t i = 0;
  int64_t rejected = 0;
  for (auto _ : state) {
    if (i == kSigned) {
      state.PauseTiming();
      receiver =
          std::make_unique<PduAuthenticator>(NodeAddress{2, 2}, PduAuthConfig{.key = BenchKey()});
      i = 0;
      state.ResumeTiming();
    }
    std::span<const uint8_t> out;
    if (receiver->Verify(batch[i++], out)) ++rejected;
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes"] = static_cast<double>(batch[0].size());
  state.counters["rejected"] = static_cast<double>(rejected);
}

// The next Construct of a burst written as a delta against the one before it, as PduBus packs
// it (Encode), and rebuilt, as a receiver does (Apply); counter: the delta's bytes.
void BM_MemberDelta(benchmark::State& state) {
  const bool apply = state.range(0) == 1;
  const auto first = sample::Construct();
  const auto previous = EncodePdu(first), member = EncodePdu(sample::NextInBurst(first));
  std::vector<uint8_t> delta;
  EncodeMemberDelta(previous, member, delta);
  std::vector<uint8_t> rebuilt(kMaxPduBytes);
  for (auto _ : state) {
    if (apply) {
      size_t length = 0;
      benchmark::DoNotOptimize(ApplyMemberDelta(previous, delta, rebuilt, &length));
      benchmark::DoNotOptimize(rebuilt.data());
    } else {
      EncodeMemberDelta(previous, member, delta);
      benchmark::DoNotOptimize(delta.data());
    }
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes"] = static_cast<double>(delta.size());
}

BENCHMARK_CAPTURE(BM_Encode, construct, sample::Construct());
BENCHMARK_CAPTURE(BM_Encode, update, sample::Update());
BENCHMARK_CAPTURE(BM_Encode, destruct, sample::Destruct());
BENCHMARK_CAPTURE(BM_Encode, max_feature, sample::MaxFeature());
BENCHMARK_CAPTURE(BM_Encode, playback, sample::Playback());
BENCHMARK_CAPTURE(BM_DecodeValidate, construct, sample::Construct());
BENCHMARK_CAPTURE(BM_DecodeValidate, update, sample::Update());
BENCHMARK_CAPTURE(BM_DecodeValidate, destruct, sample::Destruct());
BENCHMARK_CAPTURE(BM_DecodeValidate, max_feature, sample::MaxFeature());
BENCHMARK_CAPTURE(BM_DecodeValidate, playback, sample::Playback());
BENCHMARK(BM_MemberDelta)->ArgName("apply")->Arg(0)->Arg(1);
BENCHMARK_CAPTURE(BM_Sign, construct, sample::Construct());
BENCHMARK_CAPTURE(BM_Sign, update, sample::Update());
BENCHMARK_CAPTURE(BM_Sign, max_feature, sample::MaxFeature());
BENCHMARK_CAPTURE(BM_Verify, construct, sample::Construct());
BENCHMARK_CAPTURE(BM_Verify, update, sample::Update());
BENCHMARK_CAPTURE(BM_Verify, max_feature, sample::MaxFeature());

// Handles until `target` messages arrived or 2 s passed (a lost datagram must not hang the run).
template <typename HandleFn>
bool ReceiveUntil(const int64_t& received, int64_t target, HandleFn handle) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (received < target) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    handle();
  }
  return true;
}

// The PDU layer: PduBus stamps, validates and encodes; the receiver decodes and validates.
// Authenticated: the sender also signs and the receiver verifies first.
void BM_PduBusThroughput(benchmark::State& state, std::string url, bool authenticated = false) {
  auto tx = MakeTransport(url, sample::kSampleExercise);
  std::unique_ptr<Transport> rx_owned;
  Transport* rx = tx.get();
  if (url != "memq://") {
    rx_owned = MakeTransport(url, sample::kSampleExercise);
    rx = rx_owned.get();
  }
  PduBusConfig tc;
  tc.exercise_id = sample::kSampleExercise;
  tc.local = {1, 1};
  tc.terrain_size_x_m = tc.terrain_size_z_m = sample::kSampleTerrainM;
  PduBusConfig rc = tc;
  rc.local = {2, 2};
  rc.deliver_own = true;
  if (authenticated) tc.auth.key = rc.auth.key = BenchKey();
  PduBus sender(*tx, tc);
  PduBus receiver(*rx, rc);
  int64_t received = 0;
  receiver.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t&) { ++received; });
  if (auto* dds = dynamic_cast<DdsTransport*>(tx.get())) {
    dds->WaitForReaders(PduType::kUpdate, 1, 10000);
  }
  const dtpdu::update_t pdu = sample::Update();
  int64_t lost = 0;
  for (auto _ : state) {
    const int64_t target = received + kBatch;
    for (int i = 0; i < kBatch; ++i) {
      if (!sender.Publish(pdu).ok()) state.SkipWithError("publish failed");
    }
    if (!ReceiveUntil(received, target, [&] { (void)receiver.HandleTimeout(10); })) {
      lost += target - received;
      received = target;
    }
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(lost);
  state.counters["rejected"] = static_cast<double>(receiver.rejects().total());
}

// Raw LCM: the same number of same-size pre-encoded messages, lcm_publish and a counting handler.
void BM_RawLcmThroughput(benchmark::State& state, std::string url) {
  bench::RawLcmLink link(url, "DT7_UPDATE");
  const auto bytes = EncodePdu(sample::Update());
  int64_t lost = 0;
  for (auto _ : state) lost += link.Send(bytes, kBatch);
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.counters["lost"] = static_cast<double>(lost);
  state.counters["bytes"] = static_cast<double>(bytes.size());
}

BENCHMARK_CAPTURE(BM_RawLcmThroughput, memq, std::string("memq://"))->UseRealTime();
BENCHMARK_CAPTURE(BM_PduBusThroughput, memq, std::string("memq://"))->UseRealTime();
BENCHMARK_CAPTURE(BM_PduBusThroughput, memq_auth, std::string("memq://"), true)->UseRealTime();
BENCHMARK_CAPTURE(BM_RawLcmThroughput, udpm, std::string(kUdpm))->UseRealTime();
BENCHMARK_CAPTURE(BM_PduBusThroughput, udpm, std::string(kUdpm))->UseRealTime();
BENCHMARK_CAPTURE(BM_PduBusThroughput, udpm_auth, std::string(kUdpm), true)->UseRealTime();
BENCHMARK_CAPTURE(BM_PduBusThroughput, dds,
                  std::string("dds://0?config=") + DT_SOURCE_DIR +
                      "/configs/cyclonedds-loopback.xml")
    ->UseRealTime();

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  return dt::bench::RunBenchmarks(argc, argv, "pdu-bench", "warn", true,
                                  "udpm/DDS numbers use the host");
}
