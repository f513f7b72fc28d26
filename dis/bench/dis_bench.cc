// Encode and decode of DIS PDUs, and the mapping of a vehicle pose and a crater to them
// (docs/performance.md, "dis").
#include <benchmark/benchmark.h>

#include <vector>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/test/golden_pdus.h"
#include "dis/vehicle_mapping.h"

namespace {

using namespace dt::dis;

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}

VehiclePose Pose() {
  VehiclePose p;
  p.entity_id = {3, 4, 9};
  p.entity_type = {1, 1, 225, 1, 1, 3, 0};
  p.marking = "TANK-9";
  p.position_m = {1523.25, 41.5, 2870.75};
  p.attitude = {2.1, 0.05, -0.03};
  p.velocity_mps = {4.0, 0.2, -3.0};
  p.dead_reckoning = DeadReckoningAlgorithm::kRvw;
  return p;
}

template <typename Pdu>
void BM_Encode(benchmark::State& state, Pdu pdu) {
  for (auto _ : state) {
    std::vector<uint8_t> bytes = Encode(pdu);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_Encode, entity_state, dt::dis::testing::GoldenEntityState());
BENCHMARK_CAPTURE(BM_Encode, point_object, dt::dis::testing::GoldenPointObjectState());
BENCHMARK_CAPTURE(BM_Encode, linear_object, dt::dis::testing::GoldenLinearObjectState());

template <typename Pdu>
void BM_Decode(benchmark::State& state, Pdu pdu) {
  const std::vector<uint8_t> bytes = Encode(pdu);
  Decoder decoder(pdu.header.exercise_id);
  for (auto _ : state) {
    DecodeResult r = decoder.Decode(bytes);
    benchmark::DoNotOptimize(&r);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["rejected"] = static_cast<double>(decoder.counters().rejected_total());
}
BENCHMARK_CAPTURE(BM_Decode, entity_state, dt::dis::testing::GoldenEntityState());
BENCHMARK_CAPTURE(BM_Decode, point_object, dt::dis::testing::GoldenPointObjectState());
BENCHMARK_CAPTURE(BM_Decode, linear_object, dt::dis::testing::GoldenLinearObjectState());

// A pose to the bytes of its Entity State: geocentric location, Euler angles, encode.
void BM_PoseToDatagram(benchmark::State& state) {
  const VehiclePose pose = Pose();
  for (auto _ : state) {
    std::vector<uint8_t> bytes = Encode(ToEntityState(pose, Frame(), {5, 0}).value());
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PoseToDatagram);

// A received Entity State to a pose: decode, local metres, attitude.
void BM_DatagramToPose(benchmark::State& state) {
  const std::vector<uint8_t> bytes = Encode(ToEntityState(Pose(), Frame(), {5, 0}).value());
  Decoder decoder(5);
  for (auto _ : state) {
    DecodeResult r = decoder.Decode(bytes);
    auto pose = FromEntityState(std::get<EntityStatePdu>(r.pdu()), Frame());
    benchmark::DoNotOptimize(&pose);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DatagramToPose);

void BM_CraterToDatagram(benchmark::State& state) {
  const dt::FeatureParams crater = dt::FeatureParams::Crater(120, 340, 10);
  for (auto _ : state) {
    auto pdu = FeatureToDis({1, 2, 3}, crater, 12.5, 1, Frame(), {5, 0});
    std::vector<uint8_t> bytes = Encode(std::get<PointObjectStatePdu>(pdu.value()));
    benchmark::DoNotOptimize(bytes.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CraterToDatagram);

}  // namespace

BENCHMARK_MAIN();
