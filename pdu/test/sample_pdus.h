// Sample PDUs of every type, valid for exercise kSampleExercise on a kSampleTerrainM terrain.
#pragma once

#include "pdu/conversion.h"
#include "pdu/pdu_traits.h"
#include "pdu/validation.h"

namespace dt::sample {

inline constexpr uint8_t kSampleExercise = 7;
inline constexpr double kSampleTerrainM = 1000.0;
inline ValidationContext Context() { return {kSampleExercise, kSampleTerrainM}; }

template <typename Pdu>
void StampHeader(Pdu& pdu, int64_t sender_seq = 1) {
  pdu.header.protocol_version = kProtocolVersion;
  pdu.header.exercise_id = kSampleExercise;
  pdu.header.pdu_type = static_cast<uint8_t>(PduTraits<Pdu>::kType);
  pdu.header.timestamp_dis = 12345;
  pdu.sender.site = 1;
  pdu.sender.host = 2;
  pdu.sender_seq = sender_seq;
}

inline FeaturePdu Crater() {
  FeaturePdu f;
  f.id = {1, 2, 3};
  f.change = {{1, 2}, 4, 5};
  f.params = FeatureParams::Crater(100.25, 200.5, 7.5, Material::kDirt);
  f.params.vertex_edits = {{0, 1, -0.5}, {3, 2, 0.25}};
  return f;
}

inline FeaturePdu Bridge() {
  FeaturePdu f;
  f.id = {1, 2, 4};
  f.change = {{3, 4}, 9, 12};
  f.params = FeatureParams::Bridge(300, 400, 0.5, 6, 20, 40, 20, 5, 5);
  return f;
}

inline dtpdu::construct_t Construct() {
  auto pdu = ToConstruct(Crater());
  StampHeader(pdu);
  return pdu;
}

inline dtpdu::update_t Update() {
  auto pdu = ToUpdate(Bridge());
  StampHeader(pdu);
  return pdu;
}

inline dtpdu::destruct_t Destruct() {
  auto pdu = ToDestruct({{1, 2, 3}, FeatureType::kCrater, {{5, 6}, 2, 30}});
  StampHeader(pdu);
  return pdu;
}

inline dtpdu::max_feature_t MaxFeature() {
  dtpdu::max_feature_t pdu{};
  StampHeader(pdu);
  pdu.subject = ToPdu({5, 6});
  pdu.max_feature_number = 42;
  pdu.max_change_seq = 50;
  pdu.lamport = 77;
  pdu.role = static_cast<uint8_t>(NodeRole::kServer);
  pdu.sign_on = 1;
  return pdu;
}

inline dtpdu::playback_t Playback() {
  dtpdu::playback_t pdu{};
  StampHeader(pdu);
  pdu.requesting = ToPdu({1, 2});
  pdu.transmitting = ToPdu({3, 4});
  pdu.subject = ToPdu({3, 4});
  pdu.range_kind = static_cast<uint8_t>(PlaybackRange::kFeatureNumbers);
  pdu.start = 10;
  pdu.end = 20;
  pdu.is_response = 0;
  pdu.range_complete = 0;
  return pdu;
}

}  // namespace dt::sample
