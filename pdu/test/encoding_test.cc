// Checks one encoded Construct PDU byte for byte against a vector built by hand from LCM's rules,
// and that every LCM type has a fingerprint of its own.
#include <bit>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dtpdu/anti_entropy_entry_t.hpp"
#include "dtpdu/anti_entropy_t.hpp"
#include "dtpdu/batch_member_t.hpp"
#include "dtpdu/batch_t.hpp"
#include "dtpdu/crater_vertex_edit_t.hpp"
#include "dtpdu/entity_id_t.hpp"
#include "dtpdu/entity_type_t.hpp"
#include "dtpdu/header_t.hpp"
#include "dtpdu/node_address_t.hpp"
#include "dtpdu/vehicle_state_t.hpp"
#include "pdu/pdu_traits.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

// LCM's type fingerprint, from the LCM type specification: start at 0x12345678; for each member
// hash its name, its type name if primitive, its number of dimensions and, per dimension, the
// mode (0 constant, 1 variable) and the size text. Each step is v = ((v << 8) ^ (v >> 55)) + c
// with c a signed char (a string hashes its length first). The fingerprint of a struct adds the
// fingerprints of its struct-typed members, then rotates left by one bit.
struct Member {
  std::string name;
  std::string primitive;  // "" for a struct-typed member
  std::vector<std::pair<int, std::string>> dims;
};

int64_t Step(int64_t v, char c) { return ((v << 8) ^ (v >> 55)) + c; }
int64_t StepString(int64_t v, const std::string& s) {
  v = Step(v, static_cast<char>(s.size()));
  for (char c : s) v = Step(v, c);
  return v;
}
uint64_t BaseHash(const std::vector<Member>& members) {
  int64_t v = 0x12345678;
  for (const auto& m : members) {
    v = StepString(v, m.name);
    if (!m.primitive.empty()) v = StepString(v, m.primitive);
    v = Step(v, static_cast<char>(m.dims.size()));
    for (const auto& [mode, size] : m.dims) {
      v = Step(v, static_cast<char>(mode));
      v = StepString(v, size);
    }
  }
  return static_cast<uint64_t>(v);
}
uint64_t Fingerprint(uint64_t base, const std::vector<uint64_t>& children) {
  uint64_t h = base;
  for (uint64_t c : children) h += c;
  return (h << 1) + ((h >> 63) & 1);
}

uint64_t HeaderFingerprint() {
  return Fingerprint(BaseHash({{"protocol_version", "byte", {}},
                               {"exercise_id", "byte", {}},
                               {"pdu_type", "byte", {}},
                               {"timestamp_dis", "int32_t", {}}}),
                     {});
}
uint64_t AddressFingerprint() {
  return Fingerprint(BaseHash({{"site", "int16_t", {}}, {"host", "int16_t", {}}}), {});
}
uint64_t EditFingerprint() {
  return Fingerprint(
      BaseHash({{"spoke", "byte", {}}, {"ring", "byte", {}}, {"offset_m", "double", {}}}), {});
}
uint64_t PointFingerprint() {
  return Fingerprint(BaseHash({{"x_m", "double", {}},
                               {"z_m", "double", {}},
                               {"height_m", "double", {}},
                               {"width_m", "double", {}}}),
                     {});
}
// Construct and Update differ only in the name of the change's author.
uint64_t FeatureFingerprint(const std::string& author) {
  const std::vector<Member> members = {
      {"header", "", {}},
      {"sender", "", {}},
      {"sender_seq", "int64_t", {}},
      {"origin", "", {}},
      {"feature_number", "int64_t", {}},
      {"feature_type", "int16_t", {}},
      {author, "", {}},
      {"change_seq", "int64_t", {}},
      {"lamport", "int64_t", {}},
      {"is_playback", "boolean", {}},
      {"playback_for", "", {}},
      {"position_m", "double", {{0, "3"}}},
      {"direction_rad", "double", {}},
      {"height_m", "double", {{0, "2"}}},
      {"length_m", "double", {{0, "3"}}},
      {"width_m", "double", {}},
      {"material", "int16_t", {}},
      {"status", "int32_t", {}},
      {"num_vertex_edits", "int16_t", {}},
      {"vertex_edits", "", {{1, "num_vertex_edits"}}},
      {"num_points", "int16_t", {}},
      {"points", "", {{1, "num_points"}}},
  };
  return Fingerprint(
      BaseHash(members),
      {HeaderFingerprint(), AddressFingerprint(), AddressFingerprint(), AddressFingerprint(),
       AddressFingerprint(), EditFingerprint(), PointFingerprint()});
}
uint64_t ConstructFingerprint() { return FeatureFingerprint("created_by"); }
uint64_t UpdateFingerprint() { return FeatureFingerprint("changed_by"); }

// Big-endian appenders: LCM's wire order.
struct Bytes {
  std::vector<uint8_t> v;
  void U(uint64_t x, int n) {
    for (int i = n - 1; i >= 0; --i) v.push_back(static_cast<uint8_t>(x >> (8 * i)));
  }
  void D(double d) { U(std::bit_cast<uint64_t>(d), 8); }
};

TEST(Encoding, FingerprintMatchesTheIndependentComputation) {
  EXPECT_EQ(static_cast<uint64_t>(dtpdu::header_t::getHash()), HeaderFingerprint());
  EXPECT_EQ(static_cast<uint64_t>(dtpdu::node_address_t::getHash()), AddressFingerprint());
  EXPECT_EQ(static_cast<uint64_t>(dtpdu::feature_point_t::getHash()), PointFingerprint());
  EXPECT_EQ(static_cast<uint64_t>(dtpdu::construct_t::getHash()), ConstructFingerprint());
  EXPECT_EQ(static_cast<uint64_t>(dtpdu::update_t::getHash()), UpdateFingerprint());
}

// A decoder that picks the type by fingerprint (lcm-spy, lcm-logplayer tools) must tell every
// type apart: no two types of pdu/lcm may share one.
TEST(Encoding, EveryLcmTypeHasItsOwnFingerprint) {
  const std::map<std::string, int64_t> fingerprints = {
      {"header_t", dtpdu::header_t::getHash()},
      {"node_address_t", dtpdu::node_address_t::getHash()},
      {"crater_vertex_edit_t", dtpdu::crater_vertex_edit_t::getHash()},
      {"feature_point_t", dtpdu::feature_point_t::getHash()},
      {"construct_t", dtpdu::construct_t::getHash()},
      {"update_t", dtpdu::update_t::getHash()},
      {"destruct_t", dtpdu::destruct_t::getHash()},
      {"max_feature_t", dtpdu::max_feature_t::getHash()},
      {"playback_t", dtpdu::playback_t::getHash()},
      {"anti_entropy_entry_t", dtpdu::anti_entropy_entry_t::getHash()},
      {"anti_entropy_t", dtpdu::anti_entropy_t::getHash()},
      {"entity_id_t", dtpdu::entity_id_t::getHash()},
      {"entity_type_t", dtpdu::entity_type_t::getHash()},
      {"vehicle_state_t", dtpdu::vehicle_state_t::getHash()},
      {"earth_move_t", dtpdu::earth_move_t::getHash()},
      {"batch_t", dtpdu::batch_t::getHash()},
      {"batch_member_t", dtpdu::batch_member_t::getHash()},
  };
  // Every type of pdu/lcm is in the list, so a new one cannot escape the check.
  std::set<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(DT_PDU_LCM_DIR)) {
    if (entry.path().extension() == ".lcm") files.insert(entry.path().stem().string());
  }
  std::set<std::string> listed;
  for (const auto& [name, hash] : fingerprints) listed.insert(name);
  EXPECT_EQ(listed, files);
  for (auto a = fingerprints.begin(); a != fingerprints.end(); ++a) {
    for (auto b = std::next(a); b != fingerprints.end(); ++b) {
      EXPECT_NE(a->second, b->second) << a->first << " and " << b->first << " share a fingerprint";
    }
  }
}

TEST(Encoding, ConstructBytesMatchTheHandBuiltVector) {
  dtpdu::construct_t pdu{};
  pdu.header.protocol_version = 1;
  pdu.header.exercise_id = 7;
  pdu.header.pdu_type = 220;
  pdu.header.timestamp_dis = static_cast<int32_t>(0x80000001u);  // half past, absolute
  pdu.sender = ToPdu({1, 2});
  pdu.sender_seq = 3;
  pdu.origin = ToPdu({0xFFFF, 2});
  pdu.feature_number = 0x12345678;
  pdu.feature_type = 1;
  pdu.created_by = ToPdu({0xFFFF, 2});
  pdu.change_seq = 4;
  pdu.lamport = 5;
  pdu.is_playback = 1;
  pdu.playback_for = ToPdu({3, 0x1234});
  pdu.position_m[0] = 100.25;
  pdu.position_m[1] = 0.0;
  pdu.position_m[2] = 200.5;
  pdu.direction_rad = -0.0;
  pdu.height_m[0] = 0.0;
  pdu.height_m[1] = 0.0;
  pdu.length_m[0] = 7.5;
  pdu.length_m[1] = 0.0;
  pdu.length_m[2] = 0.0;
  pdu.width_m = 0.0;
  pdu.material = 2;
  pdu.status = 0;
  pdu.num_vertex_edits = 1;
  pdu.vertex_edits.push_back({3, 2, 0.25});

  Bytes e;
  e.U(ConstructFingerprint(), 8);
  e.v.insert(e.v.end(), {0x01, 0x07, 0xDC, 0x80, 0x00, 0x00, 0x01});  // header
  e.v.insert(e.v.end(), {0x00, 0x01, 0x00, 0x02});                    // sender 1:2
  e.U(3, 8);                                                          // sender_seq
  e.v.insert(e.v.end(), {0xFF, 0xFF, 0x00, 0x02});                    // origin 65535:2
  e.v.insert(e.v.end(), {0, 0, 0, 0, 0x12, 0x34, 0x56, 0x78});        // feature_number
  e.v.insert(e.v.end(), {0x00, 0x01});                                // feature_type crater
  e.v.insert(e.v.end(), {0xFF, 0xFF, 0x00, 0x02});                    // created_by
  e.U(4, 8);                                                          // change_seq
  e.U(5, 8);                                                          // lamport
  e.v.insert(e.v.end(), {0x01});                                      // is_playback
  e.v.insert(e.v.end(), {0x00, 0x03, 0x12, 0x34});                    // playback_for 3:4660
  // 100.25 = 1.56640625 * 2^6: exponent 1023 + 6 = 0x405, mantissa 0x9100000000000.
  e.v.insert(e.v.end(), {0x40, 0x59, 0x10, 0, 0, 0, 0, 0});
  e.U(0, 8);                                                 // y
  e.v.insert(e.v.end(), {0x40, 0x69, 0x10, 0, 0, 0, 0, 0});  // 200.5 = 1.56640625 * 2^7
  e.v.insert(e.v.end(), {0x80, 0, 0, 0, 0, 0, 0, 0});        // -0.0: only the sign bit
  e.U(0, 8);
  e.U(0, 8);                                              // heights
  e.v.insert(e.v.end(), {0x40, 0x1E, 0, 0, 0, 0, 0, 0});  // 7.5 = 1.875 * 2^2
  e.U(0, 8);
  e.U(0, 8);
  e.U(0, 8);                                              // width
  e.v.insert(e.v.end(), {0x00, 0x02});                    // material dirt
  e.v.insert(e.v.end(), {0, 0, 0, 0});                    // status
  e.v.insert(e.v.end(), {0x00, 0x01});                    // num_vertex_edits
  e.v.insert(e.v.end(), {0x03, 0x02});                    // spoke, ring
  e.v.insert(e.v.end(), {0x3F, 0xD0, 0, 0, 0, 0, 0, 0});  // 0.25 = 2^-2
  e.v.insert(e.v.end(), {0x00, 0x00});                    // num_points
  // Cross-check two doubles of the vector against the machine's own representation.
  Bytes check;
  check.D(100.25);
  check.D(0.25);
  EXPECT_EQ(std::vector<uint8_t>(e.v.begin() + 66, e.v.begin() + 74),
            std::vector<uint8_t>(check.v.begin(), check.v.begin() + 8));
  EXPECT_EQ(std::vector<uint8_t>(e.v.end() - 10, e.v.end() - 2),
            std::vector<uint8_t>(check.v.begin() + 8, check.v.end()));

  EXPECT_EQ(EncodePdu(pdu), e.v);
  EXPECT_EQ(e.v.size(), 156u + 10u);
}

TEST(Encoding, SenderSitsAtTheSameOffsetInEveryType) {
  auto check = [](auto pdu) {
    pdu.sender = ToPdu({0xABCD, 0x1234});
    const auto sender = PeekSender(EncodePdu(pdu));
    ASSERT_TRUE(sender.has_value());
    EXPECT_EQ(*sender, (NodeAddress{0xABCD, 0x1234}));
  };
  check(sample::Construct());
  check(sample::Update());
  check(sample::Destruct());
  check(sample::MaxFeature());
  check(sample::Playback());
  check(sample::AntiEntropySummary());
  EXPECT_EQ(PeekSender(std::vector<uint8_t>(18, 0)), std::nullopt);
}

TEST(Encoding, AntiEntropySizesAreTheDocumentedOnes) {
  // docs/pdu.md: 58 bytes, 28 per summary entry, 8 per hash.
  EXPECT_EQ(EncodePdu(sample::AntiEntropySummary()).size(), 58u + 2 * 28u);
  EXPECT_EQ(EncodePdu(sample::AntiEntropyHashes()).size(), 58u + 32 * 8u);
  EXPECT_EQ(EncodePdu(sample::AntiEntropyCopies()).size(), 58u + 2 * 8u);
}

TEST(Encoding, TheBiggestConstructFitsInOneDatagram) {
  auto pdu = sample::Construct();
  pdu.num_vertex_edits = kMaxVertexEdits;
  pdu.vertex_edits.resize(kMaxVertexEdits);
  EXPECT_EQ(EncodePdu(pdu).size(), 156u + 64u * 10u);
  EXPECT_LE(EncodePdu(pdu).size(), kMaxPduBytes);
  auto ditch = sample::DitchConstruct();
  ditch.num_points = static_cast<int16_t>(kMaxFeaturePoints);
  ditch.points.resize(kMaxFeaturePoints);
  EXPECT_EQ(EncodePdu(ditch).size(), 156u + 32u * 32u);
  EXPECT_LE(EncodePdu(ditch).size(), kMaxPduBytes);
}

}  // namespace
}  // namespace dt
