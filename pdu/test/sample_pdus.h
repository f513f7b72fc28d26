// Sample PDUs of every type, valid for exercise kSampleExercise on a kSampleTerrainM terrain.
#pragma once

#include "pdu/conversion.h"
#include "pdu/pdu_traits.h"
#include "pdu/validation.h"
#include "pdu/vehicle_state.h"

namespace dt::sample {

inline constexpr uint8_t kSampleExercise = 7;
inline constexpr double kSampleTerrainM = 1000.0;
inline ValidationContext Context() { return {kSampleExercise, kSampleTerrainM, kSampleTerrainM}; }

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

// A ditch with a spoil berm along three points, and a flooded area.
inline FeaturePdu Ditch() {
  FeaturePdu f;
  f.id = {1, 2, 5};
  f.change = {{1, 2}, 6, 7};
  f.params = FeatureParams::Ditch({{100, 100, 2, 6}, {160, 100, 2.5, 7}, {200, 140, 2, 6}}, 1.5,
                                  1.0, 3.0, Material::kDirt);
  return f;
}

inline FeaturePdu Flood() {
  FeaturePdu f;
  f.id = {1, 2, 6};
  f.change = {{1, 2}, 7, 8};
  f.params = FeatureParams::Area({{500, 500, 0, 0}, {600, 500, 0, 0}, {560, 600, 0, 0}},
                                 Material::kWater, 12.5);
  return f;
}

// Blade work: a cut of three posts and the pile they went to, a row ahead.
inline FeaturePdu EarthMove() {
  FeaturePdu f;
  f.id = {1, 2, 8};
  f.change = {{1, 2}, 9, 10};
  f.params = FeatureParams::EarthMove({{40, 50, -120},
                                       {41, 50, -150},
                                       {42, 50, -110},
                                       {40, 52, 130},
                                       {41, 52, 140},
                                       {42, 52, 110}});
  return f;
}

inline dtpdu::earth_move_t EarthMovePdu() {
  auto pdu = ToEarthMove(EarthMove());
  StampHeader(pdu);
  return pdu;
}

inline dtpdu::construct_t DitchConstruct() {
  auto pdu = ToConstruct(Ditch());
  StampHeader(pdu);
  return pdu;
}

inline dtpdu::construct_t Construct() {
  auto pdu = ToConstruct(Crater());
  StampHeader(pdu);
  return pdu;
}

// The Construct a burst sends after `pdu`: the next sequence numbers, feature and clock, 10 m on.
inline dtpdu::construct_t NextInBurst(dtpdu::construct_t pdu) {
  pdu.sender_seq += 1;
  pdu.feature_number += 1;
  pdu.change_seq += 1;
  pdu.lamport += 1;
  pdu.position_m[0] += 10.0;
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
  pdu.ground_digest[0] = static_cast<int64_t>(0x0123456789ABCDEFull);
  pdu.ground_digest[1] = static_cast<int64_t>(0xFEDCBA9876543210ull);
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

// A summary of two authors' logs.
inline dtpdu::anti_entropy_t AntiEntropySummary() {
  dtpdu::anti_entropy_t pdu{};
  StampHeader(pdu);
  pdu.kind = static_cast<uint8_t>(AntiEntropyKind::kSummary);
  pdu.role = static_cast<uint8_t>(NodeRole::kNode);
  pdu.entries.resize(2);
  pdu.entries[0].author = ToPdu({1, 2});
  pdu.entries[0].seq = 300;
  pdu.entries[0].prefix_hash = static_cast<int64_t>(0x8badf00ddeadbeefull);
  pdu.entries[0].max_held = 310;
  pdu.entries[1].author = ToPdu({5, 6});
  pdu.entries[1].seq = 12;
  pdu.entries[1].prefix_hash = 77;
  pdu.entries[1].max_held = 12;
  pdu.num_entries = 2;
  return pdu;
}

// The bucket hashes of 1..300 of author 5:6, answered to 1:2 by a server.
inline dtpdu::anti_entropy_t AntiEntropyHashes() {
  dtpdu::anti_entropy_t pdu{};
  StampHeader(pdu);
  pdu.kind = static_cast<uint8_t>(AntiEntropyKind::kHashAnswer);
  pdu.role = static_cast<uint8_t>(NodeRole::kServer);
  pdu.target = ToPdu({1, 2});
  pdu.subject = ToPdu({5, 6});
  pdu.start = 1;
  pdu.end = 300;
  for (int64_t i = 0; i < AntiEntropyBucketCount(1, 300); ++i) pdu.hashes.push_back(i * 1000003);
  pdu.num_hashes = static_cast<int16_t>(pdu.hashes.size());
  return pdu;
}

// The marker after a server's copies of 5:6's changes 40..41.
inline dtpdu::anti_entropy_t AntiEntropyCopies() {
  dtpdu::anti_entropy_t pdu{};
  StampHeader(pdu);
  pdu.kind = static_cast<uint8_t>(AntiEntropyKind::kCopies);
  pdu.role = static_cast<uint8_t>(NodeRole::kServer);
  pdu.target = ToPdu({1, 2});
  pdu.subject = ToPdu({5, 6});
  pdu.start = 40;
  pdu.end = 41;
  pdu.hashes = {static_cast<int64_t>(0xfeedfacecafebeefull), 0};  // it holds no change 41
  pdu.num_hashes = 2;
  return pdu;
}

// Tank 1:2:5 of node 1:2 turning at 8 m/s, with every field set.
inline VehicleStateFields Tank() {
  VehicleStateFields v;
  v.id = {1, 2, 5};
  v.force_id = 1;
  v.type = *EntityTypeOfVehicle("tank");
  v.location_m = {500.25, 12.5, 250.75};
  v.velocity_mps = {6.0, 0.25, 5.25};
  v.heading_rad = 0.7;
  v.pitch_rad = 0.05;
  v.roll_rad = -0.02;
  v.appearance = appearance::kOnBridge;
  v.algorithm = DeadReckoningAlgorithm::kRvw;
  v.acceleration_mps2 = {-0.5, 0.0, 0.75};
  v.angular_velocity_body_rad_s = {0.0, -0.1, 0.01};
  v.marking = "TANK-5";
  return v;
}

inline dtpdu::vehicle_state_t VehicleState() {
  auto pdu = ToVehicleState(Tank());
  StampHeader(pdu);
  return pdu;
}

}  // namespace dt::sample
