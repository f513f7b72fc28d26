#include "dis/fuzz/decode_one.h"

#include <cmath>
#include <cstdlib>
#include <span>
#include <variant>
#include <vector>

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

// What holds for every PDU the decoder accepts from `bytes` (its whole datagram or its frame of
// a bundle): it re-encodes to as many bytes and decodes to the same PDU, and its mapping to a
// vehicle pose or a feature refuses it with a reason or gives finite values.
void CheckAccepted(const Pdu& pdu, std::span<const uint8_t> bytes) {
  const std::vector<uint8_t> again_bytes = std::visit([](const auto& p) { return Encode(p); }, pdu);
  Require(again_bytes.size() == bytes.size());
  const DecodeResult again = DecodePdu(again_bytes, kFuzzExercise);
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
}

// The same bytes read as a datagram bundling PDUs (IEEE 1278.2), as the gateway reads every
// datagram: each frame's result is what that frame decoded alone gives, a framing error is the
// last result and nothing follows it, the frames cover the datagram otherwise, and the counters
// add up to the results.
void CheckBundle(std::span<const uint8_t> datagram) {
  Decoder decoder(kFuzzExercise);
  std::vector<DecodeResult> results;
  decoder.DecodeBundle(datagram, [&](DecodeResult r) { results.push_back(std::move(r)); });
  Require(!results.empty());
  uint64_t accepted = 0;
  for (const DecodeResult& r : results) accepted += r.ok() ? 1 : 0;
  const DecodeCounters& counters = decoder.counters();
  Require(counters.entity_state + counters.point_object_state + counters.linear_object_state ==
          accepted);
  Require(counters.rejected_total() == results.size() - accepted);
  if (datagram.empty() || datagram.size() > kMaxPduSize) {
    Require(results.size() == 1 && !results[0].ok());
    return;
  }
  size_t offset = 0;
  for (size_t i = 0; i < results.size(); ++i) {
    Require(offset < datagram.size());
    const PduFrame frame = FrameAt(datagram, offset);
    if (frame.error) {
      Require(i + 1 == results.size() && !results[i].ok());
      return;
    }
    const DecodeResult alone = DecodePdu(frame.bytes, kFuzzExercise);
    Require(alone.ok() == results[i].ok());
    if (alone.ok()) {
      Require(alone.pdu() == results[i].pdu());
      CheckAccepted(results[i].pdu(), frame.bytes);
    }
    offset += frame.bytes.size();
  }
  Require(offset == datagram.size());
}

}  // namespace

bool DecodeOne(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> datagram(data, size);
  CheckBundle(datagram);
  Decoder decoder(kFuzzExercise);
  const DecodeResult result = decoder.Decode(datagram);
  if (!result.ok()) {
    Require(decoder.counters().rejected_total() == 1);
    Require(!result.error().message.empty());
    return false;
  }
  CheckAccepted(result.pdu(), datagram);
  return true;
}

}  // namespace dt::dis::fuzz
