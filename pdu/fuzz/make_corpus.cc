// pdu_fuzz_corpus: writes the seed corpus of the decode+validate fuzzer: valid PDUs of every
// type and classic malformations of them, each prefixed with the type-selector byte.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "pdu/batch.h"
#include "pdu/fuzz/decode_validate.h"
#include "pdu/pdu_auth.h"
#include "pdu/test/sample_pdus.h"

namespace {

int written = 0;

void Write(const std::string& dir, const std::string& name, uint8_t selector,
           std::vector<uint8_t> bytes) {
  bytes.insert(bytes.begin(), selector);
  std::ofstream(dir + "/" + name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  ++written;
}

template <typename Pdu>
void Family(const std::string& dir, const std::string& stem, uint8_t selector, const Pdu& pdu) {
  const auto good = dt::EncodePdu(pdu);
  Write(dir, stem + "_valid", selector, good);
  Write(dir, stem + "_truncated", selector, {good.begin(), good.end() - 1});
  Write(dir, stem + "_fingerprint_only", selector, {good.begin(), good.begin() + 8});
  auto trailing = good;
  trailing.push_back(0xAA);
  Write(dir, stem + "_trailing", selector, trailing);
  auto flipped = good;
  flipped[2] ^= 0x01;
  Write(dir, stem + "_bad_fingerprint", selector, flipped);
  Pdu version = pdu;
  version.header.protocol_version = 9;
  Write(dir, stem + "_bad_version", selector, dt::EncodePdu(version));
  Pdu exercise = pdu;
  exercise.header.exercise_id = 8;
  Write(dir, stem + "_foreign_exercise", selector, dt::EncodePdu(exercise));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus-dir>\n", argv[0]);
    return 2;
  }
  using namespace dt;
  const std::string dir = argv[1];
  Family(dir, "construct", 0, sample::Construct());
  Family(dir, "update", 1, sample::Update());
  Family(dir, "destruct", 2, sample::Destruct());
  Family(dir, "maxfeature", 3, sample::MaxFeature());
  Family(dir, "playback", 4, sample::Playback());
  Family(dir, "antientropy", 5, sample::AntiEntropySummary());
  Family(dir, "antientropy_hashes", 5, sample::AntiEntropyHashes());
  Family(dir, "vehiclestate", 6, sample::VehicleState());
  // Signed by the samples' sender with the fuzz key and clock (selector + kFuzzTypes:
  // authenticated).
  constexpr uint8_t kSigned = fuzz::kFuzzTypes;
  auto key = std::make_shared<const ExerciseKey>(fuzz::FuzzKey());
  PduAuthenticator signer({1, 2}, PduAuthConfig{.key = key,
                                                .wall_clock_ms = [] { return fuzz::kFuzzClockMs; },
                                                .incarnation = 1});
  auto signed_pdu = [&](std::vector<uint8_t> bytes) {
    signer.Sign(bytes);
    return bytes;
  };
  Write(dir, "signed_construct_valid", kSigned + 0, signed_pdu(EncodePdu(sample::Construct())));
  Write(dir, "signed_update_valid", kSigned + 1, signed_pdu(EncodePdu(sample::Update())));
  Write(dir, "signed_maxfeature_valid", kSigned + 3, signed_pdu(EncodePdu(sample::MaxFeature())));
  auto forged = signed_pdu(EncodePdu(sample::Destruct()));
  forged[forged.size() - 1] ^= 0x01;  // the MAC's last byte
  Write(dir, "signed_destruct_bad_mac", kSigned + 2, forged);
  auto old_magic = signed_pdu(EncodePdu(sample::Playback()));
  old_magic[EncodePdu(sample::Playback()).size() + 3] = '1';  // DTA1: the HMAC trailer
  Write(dir, "signed_playback_old_trailer", kSigned + 4, old_magic);
  Family(dir, "antientropy_copies", 5, sample::AntiEntropyCopies());

  // Batches (selector kFuzzBatch): taken whole, or refused whole for one bad member.
  const auto batch = [](const std::vector<std::pair<PduType, std::vector<uint8_t>>>& m,
                        MemberEncoding encoding = MemberEncoding::kWhole) {
    std::vector<BatchMember> members;
    for (const auto& [type, bytes] : m) members.push_back({type, bytes, encoding});
    std::vector<uint8_t> out;
    EncodeBatchInto(sample::kSampleExercise, 12345, {1, 2}, members, out);
    return out;
  };
  const std::pair<PduType, std::vector<uint8_t>> update{PduType::kUpdate,
                                                        EncodePdu(sample::Update())};
  const std::pair<PduType, std::vector<uint8_t>> vehicle{PduType::kVehicleState,
                                                         EncodePdu(sample::VehicleState())};
  const auto good_batch = batch({update,
                                 {PduType::kConstruct, EncodePdu(sample::Construct())},
                                 vehicle,
                                 {PduType::kEarthMove, EncodePdu(sample::EarthMovePdu())}});
  Write(dir, "batch_valid", fuzz::kFuzzBatch, good_batch);
  Write(dir, "batch_truncated", fuzz::kFuzzBatch, {good_batch.begin(), good_batch.end() - 1});
  auto bad_member = sample::Construct();
  bad_member.length_m[0] = -1;
  Write(dir, "batch_bad_member", fuzz::kFuzzBatch,
        batch({update, {PduType::kConstruct, EncodePdu(bad_member)}, vehicle}));
  auto stranger = sample::Destruct();
  stranger.sender.host = 3;
  Write(dir, "batch_stranger_member", fuzz::kFuzzBatch,
        batch({update, {PduType::kDestruct, EncodePdu(stranger)}}));
  Write(dir, "batch_nested", fuzz::kFuzzBatch, batch({update, {PduType::kBatch, batch({update})}}));
  Write(dir, "batch_mislabelled_member", fuzz::kFuzzBatch,
        batch({{PduType::kDestruct, update.second}, vehicle}));
  Write(dir, "batch_empty", fuzz::kFuzzBatch, batch({}));
  auto old = batch({update, vehicle});
  old[8] = kProtocolVersion - 1;  // header.protocol_version, right after the fingerprint
  Write(dir, "batch_old_version", fuzz::kFuzzBatch, old);
  Write(dir, "signed_batch_valid", fuzz::kFuzzBatch + kSigned, signed_pdu(good_batch));
  // Members as deltas (docs/pdu.md "Member deltas"): a burst of Constructs as PduBus packs it.
  std::vector<std::pair<PduType, std::vector<uint8_t>>> deltas;
  std::vector<uint8_t> previous;
  for (int k = 0; k < 4; ++k) {
    auto construct = sample::Construct();
    construct.sender_seq += k;
    construct.feature_number += k;
    construct.change_seq += k;
    construct.position_m[0] += 10.0 * k;
    const auto whole = EncodePdu(construct);
    std::vector<uint8_t> delta;
    EncodeMemberDelta(previous, whole, delta);
    deltas.emplace_back(PduType::kConstruct, k == 0 ? whole : delta);
    previous = whole;
  }
  // The first member whole, the others as the deltas they hold.
  const auto delta_batch = [](const std::vector<std::pair<PduType, std::vector<uint8_t>>>& m) {
    std::vector<BatchMember> members;
    for (size_t k = 0; k < m.size(); ++k) {
      members.push_back(
          {m[k].first, m[k].second, k == 0 ? MemberEncoding::kWhole : MemberEncoding::kDelta});
    }
    std::vector<uint8_t> out;
    EncodeBatchInto(sample::kSampleExercise, 12345, {1, 2}, members, out);
    return out;
  };
  Write(dir, "batch_deltas_valid", fuzz::kFuzzBatch, delta_batch(deltas));
  Write(dir, "batch_delta_first", fuzz::kFuzzBatch,
        batch({{PduType::kConstruct, deltas[1].second}}, MemberEncoding::kDelta));
  auto long_run = deltas;
  long_run[1].second[0] = 0;  // the delta's length: 1 byte, so its runs end past the member
  long_run[1].second[1] = 1;
  Write(dir, "batch_delta_past_end", fuzz::kFuzzBatch, delta_batch(long_run));
  auto unknown_encoding = good_batch;
  unknown_encoding[kBatchBaseBytes + 1] = 2;  // the first member's encoding
  Write(dir, "batch_unknown_encoding", fuzz::kFuzzBatch, unknown_encoding);

  auto c = sample::Construct();
  c.position_m[0] = std::numeric_limits<double>::quiet_NaN();
  Write(dir, "construct_nan", 0, EncodePdu(c));
  c = sample::Construct();
  c.length_m[0] = 1e300;
  Write(dir, "construct_huge_radius", 0, EncodePdu(c));
  c = sample::Construct();
  c.position_m[2] = -5;
  Write(dir, "construct_off_terrain", 0, EncodePdu(c));
  c = sample::Construct();
  c.num_vertex_edits = kMaxVertexEdits;
  c.vertex_edits.resize(kMaxVertexEdits);
  for (int i = 0; i < kMaxVertexEdits; ++i) {
    c.vertex_edits[static_cast<size_t>(i)] = {static_cast<uint8_t>(i / 4),
                                              static_cast<uint8_t>(i % 4), 0.5};
  }
  Write(dir, "construct_all_edits", 0, EncodePdu(c));
  auto neg = EncodePdu(sample::Construct());
  neg[neg.size() - 24] = 0xFF;  // negative num_vertex_edits (then 2 edits and num_points)
  Write(dir, "construct_negative_count", 0, neg);
  Family(dir, "construct_ditch", 0, sample::DitchConstruct());
  c = sample::DitchConstruct();
  c.points[1].x_m = 99;  // turns back on itself at points[1]
  Write(dir, "construct_ditch_sharp_turn", 0, EncodePdu(c));
  c = sample::DitchConstruct();
  c.points[2].z_m = -1;
  Write(dir, "construct_ditch_point_off_terrain", 0, EncodePdu(c));
  c = sample::DitchConstruct();
  c.points[1].width_m = std::numeric_limits<double>::infinity();
  Write(dir, "construct_ditch_point_infinite", 0, EncodePdu(c));
  c = sample::DitchConstruct();
  c.num_points = static_cast<int16_t>(kMaxFeaturePoints);
  c.points.resize(kMaxFeaturePoints);
  for (int i = 0; i < kMaxFeaturePoints; ++i) {
    c.points[static_cast<size_t>(i)] = {100.0 + 20 * i, 100, 2, 6};
  }
  Write(dir, "construct_ditch_max_points_valid", 0, EncodePdu(c));
  auto flood = ToConstruct(sample::Flood());
  sample::StampHeader(flood);
  Write(dir, "construct_flood_valid", 0, EncodePdu(flood));
  flood.height_m[0] = std::numeric_limits<double>::quiet_NaN();
  Write(dir, "construct_flood_nan_level", 0, EncodePdu(flood));
  auto u = sample::Update();
  u.material = 77;
  Write(dir, "update_bad_material", 1, EncodePdu(u));
  u = sample::Update();
  u.feature_type = 0;
  Write(dir, "update_bad_type", 1, EncodePdu(u));
  auto p = sample::Playback();
  p.start = 50;
  p.end = 10;
  Write(dir, "playback_inverted", 4, EncodePdu(p));
  p = sample::Playback();
  p.end = kMaxSerial;
  Write(dir, "playback_huge", 4, EncodePdu(p));
  auto ae = sample::AntiEntropySummary();
  ae.kind = 9;
  Write(dir, "antientropy_bad_kind", 5, EncodePdu(ae));
  ae = sample::AntiEntropySummary();
  ae.entries[1].max_held = 0;
  Write(dir, "antientropy_zero_seq", 5, EncodePdu(ae));
  ae = sample::AntiEntropyHashes();
  ae.hashes.pop_back();
  ae.num_hashes = static_cast<int16_t>(ae.hashes.size());
  Write(dir, "antientropy_short_hashes", 5, EncodePdu(ae));
  ae = sample::AntiEntropyHashes();
  ae.start = 301;
  Write(dir, "antientropy_inverted", 5, EncodePdu(ae));
  ae = sample::AntiEntropyCopies();
  ae.end = ae.start + kMaxCopySpan;
  Write(dir, "antientropy_huge_copies", 5, EncodePdu(ae));
  ae = sample::AntiEntropyCopies();
  ae.hashes.pop_back();
  ae.num_hashes = 1;
  Write(dir, "antientropy_copies_short_hashes", 5, EncodePdu(ae));
  Write(dir, "signed_vehiclestate_valid", kSigned + 6,
        signed_pdu(EncodePdu(sample::VehicleState())));
  auto v = sample::VehicleState();
  v.linear_velocity_mps[0] = std::numeric_limits<double>::infinity();
  Write(dir, "vehiclestate_infinite_velocity", 6, EncodePdu(v));
  v = sample::VehicleState();
  v.linear_velocity_mps[2] = 400.0;
  Write(dir, "vehiclestate_absurd_speed", 6, EncodePdu(v));
  v = sample::VehicleState();
  v.location_m[0] = 1000.5;
  Write(dir, "vehiclestate_off_terrain", 6, EncodePdu(v));
  v = sample::VehicleState();
  v.entity_type.category = 99;
  Write(dir, "vehiclestate_unknown_type", 6, EncodePdu(v));
  v = sample::VehicleState();
  v.dead_reckoning_algorithm = 9;
  Write(dir, "vehiclestate_bad_algorithm", 6, EncodePdu(v));
  v = sample::VehicleState();
  v.appearance = static_cast<int32_t>(1u << 31);
  Write(dir, "vehiclestate_bad_appearance", 6, EncodePdu(v));
  Family(dir, "earthmove", 7, sample::EarthMovePdu());
  Write(dir, "signed_earthmove_valid", kSigned + 7, signed_pdu(EncodePdu(sample::EarthMovePdu())));
  auto em = sample::EarthMovePdu();
  em.delta_mm[2] = 0;
  Write(dir, "earthmove_zero_delta", 7, EncodePdu(em));
  em = sample::EarthMovePdu();
  em.changed_mask[0] ^= 0x02;  // one more post set than deltas sent
  Write(dir, "earthmove_mask_disagrees", 7, EncodePdu(em));
  em = sample::EarthMovePdu();
  em.columns = 49;
  Write(dir, "earthmove_wide", 7, EncodePdu(em));
  em = sample::EarthMovePdu();
  em.first_post_i = -1;
  Write(dir, "earthmove_negative_post", 7, EncodePdu(em));
  em = sample::EarthMovePdu();
  em.moved_by.host = 9;
  Write(dir, "earthmove_not_origin", 7, EncodePdu(em));
  Write(dir, "empty", 0, {});
  std::printf("wrote %d inputs to %s\n", written, dir.c_str());
  return 0;
}
