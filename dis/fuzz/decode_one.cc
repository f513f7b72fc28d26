#include "dis/fuzz/decode_one.h"

#include <cmath>
#include <cstdlib>
#include <span>
#include <variant>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/vehicle_mapping.h"

namespace dt::dis::fuzz {
namespace {

void Require(bool condition) {
  if (!condition) std::abort();
}

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}

bool Finite(const LocalPoint& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.z_m);
}

void CheckFeature(const ObjectStatePdu& pdu) {
  const auto feature = FeatureFromDisPdu(pdu, Frame());
  if (!feature.ok()) {
    Require(!feature.error().message.empty());
    return;
  }
  const FeatureFromDis& f = feature.value();
  Require(std::isfinite(f.ground_elevation_m));
  if (!f.complete) return;
  // Accepted features go back to DIS without misuse (an ID may still lack a DIS number).
  const auto again = FeatureToDis(f.id, f.params, f.ground_elevation_m, f.update_number, Frame(),
                                  {kFuzzExercise, 0});
  if (again.ok()) Require(again.value().index() == pdu.index());
}

}  // namespace

bool DecodeOne(const uint8_t* data, size_t size) {
  Decoder decoder(kFuzzExercise);
  const DecodeResult result = decoder.Decode(std::span<const uint8_t>(data, size));
  if (!result.ok()) {
    Require(decoder.counters().rejected_total() == 1);
    Require(!result.error().message.empty());
    return false;
  }
  const Pdu& pdu = result.pdu();
  const std::vector<uint8_t> bytes = std::visit([](const auto& p) { return Encode(p); }, pdu);
  Require(bytes.size() == size);
  const DecodeResult again = DecodePdu(bytes, kFuzzExercise);
  Require(again.ok());
  Require(again.pdu() == pdu);
  if (const auto* es = std::get_if<EntityStatePdu>(&pdu)) {
    const auto pose = FromEntityState(*es, Frame());
    if (pose.ok()) {
      Require(Finite(pose.value().position_m));
      Require(Finite(pose.value().velocity_mps));
      Require(std::isfinite(pose.value().attitude.heading_rad));
      Require(std::isfinite(pose.value().attitude.pitch_rad));
      Require(std::isfinite(pose.value().attitude.roll_rad));
    }
  } else if (const auto* point = std::get_if<PointObjectStatePdu>(&pdu)) {
    CheckFeature(*point);
  } else {
    CheckFeature(std::get<LinearObjectStatePdu>(pdu));
  }
  return true;
}

}  // namespace dt::dis::fuzz
