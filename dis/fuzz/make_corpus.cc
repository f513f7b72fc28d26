// dis_fuzz_corpus: writes the seed corpus of the DIS decoder fuzzer: valid PDUs of every type
// (exercise kFuzzExercise) and classic malformations of them.
//   dis_fuzz_corpus dis/fuzz/corpus
#include <bit>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/fuzz/decode_one.h"
#include "dis/test/golden_pdus.h"
#include "dis/vehicle_mapping.h"

namespace {

using namespace dt::dis;
int written = 0;

void Write(const std::string& dir, const std::string& name, const std::vector<uint8_t>& bytes) {
  std::ofstream(dir + "/" + name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  ++written;
}

void SetLength(std::vector<uint8_t>& b, size_t n) {
  b[8] = static_cast<uint8_t>(n >> 8);
  b[9] = static_cast<uint8_t>(n);
}

// Valid, and the malformations every PDU type gets.
void Family(const std::string& dir, const std::string& stem, const std::vector<uint8_t>& good) {
  Write(dir, stem + "_valid", good);
  Write(dir, stem + "_truncated", {good.begin(), good.end() - 1});
  Write(dir, stem + "_header_only", {good.begin(), good.begin() + kHeaderSize});
  auto trailing = good;
  trailing.push_back(0xAA);
  Write(dir, stem + "_trailing", trailing);
  auto trailing_fixed = trailing;
  SetLength(trailing_fixed, trailing.size());
  Write(dir, stem + "_trailing_length_fixed", trailing_fixed);
  auto foreign = good;
  foreign[1] = dt::dis::fuzz::kFuzzExercise + 1;
  Write(dir, stem + "_foreign_exercise", foreign);
  auto version = good;
  version[0] = 8;
  Write(dir, stem + "_bad_version", version);
  auto family = good;
  family[3] = 4;
  Write(dir, stem + "_bad_family", family);
  auto length = good;
  SetLength(length, good.size() + 16);
  Write(dir, stem + "_length_too_big", length);
}

void PutNan(std::vector<uint8_t>& b, size_t at) {
  const uint64_t nan = std::bit_cast<uint64_t>(std::numeric_limits<double>::quiet_NaN());
  for (int i = 0; i < 8; ++i) b[at + i] = static_cast<uint8_t>(nan >> (56 - 8 * i));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus dir>\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  auto es = testing::GoldenEntityState();
  es.header.exercise_id = dt::dis::fuzz::kFuzzExercise;
  Family(dir, "entity_state", Encode(es));
  auto with_parameters = es;
  with_parameters.variable_parameters.resize(2);
  Family(dir, "entity_state_parameters", Encode(with_parameters));
  auto point = testing::GoldenPointObjectState();
  point.header.exercise_id = dt::dis::fuzz::kFuzzExercise;
  Family(dir, "point_object", Encode(point));
  auto linear = testing::GoldenLinearObjectState();
  linear.header.exercise_id = dt::dis::fuzz::kFuzzExercise;
  Family(dir, "linear_object", Encode(linear));

  // Mapped features and a vehicle, as the gateway sends them.
  const GeodeticFrame frame({36.6, -121.9, 20.0});
  const PduContext context{dt::dis::fuzz::kFuzzExercise, 0};
  const dt::FeatureId id{1, 2, 3};
  for (const auto& [name, params] :
       {std::pair{"crater", dt::FeatureParams::Crater(10, 20, 5)},
        std::pair{"berm", dt::FeatureParams::Berm(10, 20, 0.5, 30, 4, 2)},
        std::pair{"bridge", dt::FeatureParams::Bridge(10, 20, 1, 6, 10, 30, 10, 3, 3)}}) {
    const auto pdu = FeatureToDis(id, params, 4.0, 1, frame, context).value();
    std::visit(
        [&](const auto& p) { Write(dir, std::string("mapped_") + name + "_valid", Encode(p)); },
        pdu);
  }
  VehiclePose pose;
  pose.entity_id = {1, 2, 3};
  pose.marking = "FUZZ";
  pose.position_m = {100, 5, 200};
  Write(dir, "mapped_vehicle_valid", Encode(ToEntityState(pose, frame, context).value()));

  // Type-specific malformations.
  auto nan_location = Encode(es);
  PutNan(nan_location, 48);
  Write(dir, "entity_state_nan_location", nan_location);
  auto bad_dr = Encode(es);
  bad_dr[88] = 77;
  Write(dir, "entity_state_bad_dead_reckoning", bad_dr);
  auto count = Encode(es);
  count[19] = 3;
  Write(dir, "entity_state_parameter_count_too_big", count);
  auto unknown = Encode(es);
  unknown[2] = 2;
  Write(dir, "unknown_pdu_type", unknown);
  auto segments = Encode(linear);
  segments[27] = 4;
  Write(dir, "linear_object_segment_count_too_big", segments);
  auto nan_point = Encode(point);
  PutNan(nan_point, 32);
  Write(dir, "point_object_nan_location", nan_point);
  Write(dir, "empty", {});

  // Bundles (IEEE 1278.2: PDUs concatenated, each framed by its own length), which the gateway
  // splits: none is one whole PDU, so none is "_valid" for DecodeOne's answer.
  auto bundle = [](std::initializer_list<std::vector<uint8_t>> parts) {
    std::vector<uint8_t> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
  };
  Write(dir, "bundle_entity_point_linear", bundle({Encode(es), Encode(point), Encode(linear)}));
  Write(dir, "bundle_bad_between_good", bundle({Encode(es), nan_location, Encode(point)}));
  const auto whole = Encode(es);
  Write(dir, "bundle_truncated_tail",
        bundle({Encode(point), std::vector<uint8_t>(whole.begin(), whole.end() - 5)}));
  auto short_length = Encode(es);
  SetLength(short_length, 4);
  Write(dir, "bundle_length_below_header", bundle({Encode(point), short_length}));
  std::printf("wrote %d corpus files to %s\n", written, dir.c_str());
  return 0;
}
