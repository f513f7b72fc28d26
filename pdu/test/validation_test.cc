// Tests that every rejection reason is detected, counted and rate-limited, and valid PDUs pass.
#include "pdu/validation.h"

#include <cmath>
#include <limits>
#include <set>
#include <type_traits>

#include <gtest/gtest.h>

#include "pdu/auth_trailer.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

using sample::Context;

template <typename Pdu>
std::optional<RejectReason> ReasonFor(const Pdu& pdu, const ValidationContext& ctx = Context()) {
  Pdu out;
  auto r = DecodeAndValidate(std::span<const uint8_t>(EncodePdu(pdu)), ctx, out);
  if (!r) return std::nullopt;
  EXPECT_FALSE(r->detail.empty());
  return r->reason;
}

template <typename Pdu>
std::optional<RejectReason> ReasonForBytes(std::vector<uint8_t> bytes) {
  Pdu out;
  auto r = DecodeAndValidate(std::span<const uint8_t>(bytes), Context(), out);
  if (!r) return std::nullopt;
  return r->reason;
}

TEST(Validation, SamplesOfEveryTypePassAndDecodeToWhatWasSent) {
  EXPECT_EQ(ReasonFor(sample::Construct()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::Update()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::Destruct()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::MaxFeature()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::Playback()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::AntiEntropySummary()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::AntiEntropyHashes()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::AntiEntropyCopies()), std::nullopt);
  EXPECT_EQ(ReasonFor(sample::VehicleState()), std::nullopt);
  dtpdu::construct_t out;
  const auto bytes = EncodePdu(sample::Construct());
  ASSERT_EQ(DecodeAndValidate(std::span<const uint8_t>(bytes), Context(), out), std::nullopt);
  EXPECT_EQ(EncodePdu(out), bytes);
}

TEST(Validation, Oversized) {
  std::vector<uint8_t> bytes = EncodePdu(sample::Construct());
  bytes.resize(kMaxPduBytes + 1);
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(bytes), RejectReason::kOversized);
}

TEST(Validation, Truncated) {
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>({}), RejectReason::kTruncated);
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>({1, 2, 3}), RejectReason::kTruncated);
  // Each type on its own channel: Construct and Update have different fingerprints.
  auto expect_every_cut_truncated = [](const auto& pdu) {
    using Pdu = std::remove_cvref_t<decltype(pdu)>;
    const auto full = EncodePdu(pdu);
    for (size_t n = 8; n < full.size(); n += 5) {
      std::vector<uint8_t> cut(full.begin(), full.begin() + static_cast<long>(n));
      EXPECT_EQ(ReasonForBytes<Pdu>(cut), RejectReason::kTruncated) << n;
    }
  };
  expect_every_cut_truncated(sample::Construct());
  expect_every_cut_truncated(sample::Update());
  const auto full = EncodePdu(sample::Playback());
  EXPECT_EQ(ReasonForBytes<dtpdu::playback_t>({full.begin(), full.end() - 1}),
            RejectReason::kTruncated);
}

TEST(Validation, TruncatedWhenTheArrayLengthIsNegativeOrTooLong) {
  auto pdu = sample::Construct();
  std::vector<uint8_t> bytes = EncodePdu(pdu);
  // num_vertex_edits is the int16 just before the 2 edits of 10 bytes each (and num_points).
  const size_t at = bytes.size() - 2 - 2 * 10 - 2;
  ASSERT_EQ(bytes[at], 0);
  ASSERT_EQ(bytes[at + 1], 2);
  bytes[at] = 0xFF;  // -254
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(bytes), RejectReason::kTruncated);
  bytes[at] = 0x7F;  // 32514 edits in 20 bytes
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(bytes), RejectReason::kTruncated);
}

TEST(Validation, WrongFingerprint) {
  std::vector<uint8_t> bytes = EncodePdu(sample::Construct());
  bytes[3] ^= 0x10;
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(bytes), RejectReason::kWrongFingerprint);
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(EncodePdu(sample::Destruct())),
            RejectReason::kWrongFingerprint);
  EXPECT_EQ(ReasonForBytes<dtpdu::playback_t>(EncodePdu(sample::MaxFeature())),
            RejectReason::kWrongFingerprint);
}

TEST(Validation, TrailingBytes) {
  std::vector<uint8_t> bytes = EncodePdu(sample::Destruct());
  bytes.push_back(0);
  EXPECT_EQ(ReasonForBytes<dtpdu::destruct_t>(bytes), RejectReason::kTrailingBytes);
}

TEST(Validation, WrongProtocolVersion) {
  auto pdu = sample::MaxFeature();
  pdu.header.protocol_version = kProtocolVersion + 1;
  EXPECT_EQ(ReasonFor(pdu), RejectReason::kWrongProtocolVersion);
}

TEST(Validation, ForeignExercise) {
  EXPECT_EQ(ReasonFor(sample::Construct(), {sample::kSampleExercise + 1, 1000.0}),
            RejectReason::kForeignExercise);
}

TEST(Validation, UnknownPduType) {
  auto pdu = sample::Destruct();
  pdu.header.pdu_type = 1;  // a DIS Entity State PDU
  EXPECT_EQ(ReasonFor(pdu), RejectReason::kUnknownPduType);
}

TEST(Validation, PduTypeMismatch) {
  // Construct and Update share their fields but not their fingerprint (docs/pdu.md "Encoding"),
  // so an Update published on the Construct channel is refused by the fingerprint...
  ASSERT_NE(dtpdu::construct_t::getHash(), dtpdu::update_t::getHash());
  EXPECT_EQ(ReasonForBytes<dtpdu::construct_t>(EncodePdu(sample::Update())),
            RejectReason::kWrongFingerprint);
  EXPECT_EQ(ReasonForBytes<dtpdu::update_t>(EncodePdu(sample::Construct())),
            RejectReason::kWrongFingerprint);
  // ...and a header naming another type than the channel's by the header check.
  auto c = sample::Construct();
  c.header.pdu_type = static_cast<uint8_t>(PduType::kUpdate);
  EXPECT_EQ(ReasonFor(c), RejectReason::kPduTypeMismatch);
  auto u = sample::Update();
  u.header.pdu_type = static_cast<uint8_t>(PduType::kConstruct);
  EXPECT_EQ(ReasonFor(u), RejectReason::kPduTypeMismatch);
}

TEST(Validation, UnknownFeatureType) {
  auto c = sample::Construct();
  c.feature_type = 9;
  EXPECT_EQ(ReasonFor(c), RejectReason::kUnknownFeatureType);
  auto d = sample::Destruct();
  d.feature_type = -1;
  EXPECT_EQ(ReasonFor(d), RejectReason::kUnknownFeatureType);
}

TEST(Validation, UnknownMaterial) {
  auto u = sample::Update();
  u.material = kMaterialCount;
  EXPECT_EQ(ReasonFor(u), RejectReason::kUnknownMaterial);
  u.material = -3;
  EXPECT_EQ(ReasonFor(u), RejectReason::kUnknownMaterial);
}

TEST(Validation, NotFinite) {
  const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  for (double v : bad) {
    auto c = sample::Construct();
    c.position_m[0] = v;
    EXPECT_EQ(ReasonFor(c), RejectReason::kNotFinite);
    c = sample::Construct();
    c.position_m[1] = v;
    EXPECT_EQ(ReasonFor(c), RejectReason::kNotFinite);
    c = sample::Construct();
    c.vertex_edits[1].offset_m = v;
    EXPECT_EQ(ReasonFor(c), RejectReason::kNotFinite);
    auto u = sample::Update();
    u.direction_rad = v;
    EXPECT_EQ(ReasonFor(u), RejectReason::kNotFinite);
    u = sample::Update();
    u.width_m = v;
    EXPECT_EQ(ReasonFor(u), RejectReason::kNotFinite);
    u = sample::Update();
    u.height_m[1] = v;
    EXPECT_EQ(ReasonFor(u), RejectReason::kNotFinite);
    u = sample::Update();
    u.length_m[2] = v;
    EXPECT_EQ(ReasonFor(u), RejectReason::kNotFinite);
  }
}

TEST(Validation, SizesAtOrBelowZeroOrBeyondTheMaxima) {
  auto c = sample::Construct();
  c.length_m[0] = 0.0;
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
  c.length_m[0] = -1.0;
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
  c.length_m[0] = kMaxCraterRadiusM;
  EXPECT_EQ(ReasonFor(c), std::nullopt);
  c.length_m[0] = std::nextafter(kMaxCraterRadiusM, 1e9);
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
  auto u = sample::Update();
  u.width_m = kMaxBridgeWidthM * 2;
  EXPECT_EQ(ReasonFor(u), RejectReason::kOutOfRange);
  u = sample::Update();
  u.height_m[0] = 0.0;
  EXPECT_EQ(ReasonFor(u), RejectReason::kOutOfRange);
  // Vertex edits out of order are inconsistent feature fields.
  c = sample::Construct();
  std::swap(c.vertex_edits[0], c.vertex_edits[1]);
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
}

TEST(Validation, TheFeatureParameterBoundsRefuseAPdu) {
  // The bounds of ValidateFeatureParams, not a rule of their own: a subnormal radius, a size just
  // under the minimum, a direction of many turns.
  auto c = sample::Construct();
  c.length_m[0] = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
  c.length_m[0] = std::nextafter(kMinFeatureSizeM, 0.0);
  EXPECT_EQ(ReasonFor(c), RejectReason::kOutOfRange);
  c.length_m[0] = kMinFeatureSizeM;
  EXPECT_EQ(ReasonFor(c), std::nullopt);
  auto u = sample::Update();
  u.direction_rad = 1e300;
  EXPECT_EQ(ReasonFor(u), RejectReason::kOutOfRange);
  u.direction_rad = -kMaxDirectionRad;
  EXPECT_EQ(ReasonFor(u), std::nullopt);
  u = sample::Update();
  u.height_m[1] = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(ReasonFor(u), RejectReason::kOutOfRange);
}

TEST(Validation, OffTerrain) {
  auto c = sample::Construct();
  c.position_m[0] = -0.001;
  EXPECT_EQ(ReasonFor(c), RejectReason::kOffTerrain);
  c = sample::Construct();
  c.position_m[2] = sample::kSampleTerrainM + 0.001;
  EXPECT_EQ(ReasonFor(c), RejectReason::kOffTerrain);
  c.position_m[2] = sample::kSampleTerrainM;  // the edge is on the terrain
  EXPECT_EQ(ReasonFor(c), std::nullopt);
  auto u = sample::Update();
  u.position_m[0] = 1e6;
  EXPECT_EQ(ReasonFor(u), RejectReason::kOffTerrain);
}

// On a rectangular terrain each axis has its own bound, named in the refusal.
TEST(Validation, ARectangularTerrainBoundsXAndZApart) {
  ValidationContext wide = Context();
  wide.terrain_size_x_m = 1000.0;
  wide.terrain_size_z_m = 220.0;
  auto detail = [&](const auto& pdu) {
    std::remove_cvref_t<decltype(pdu)> out;
    auto r = DecodeAndValidate(std::span<const uint8_t>(EncodePdu(pdu)), wide, out);
    return r ? std::pair{std::optional(r->reason), r->detail}
             : std::pair{std::optional<RejectReason>(), std::string()};
  };
  auto c = sample::Construct();  // a crater at (100.25, 200.5)
  c.position_m[0] = 1000.0;      // the far x edge is on the terrain
  EXPECT_EQ(detail(c).first, std::nullopt) << detail(c).second;
  c.position_m[2] = 220.0;  // and so is the far z edge
  EXPECT_EQ(detail(c).first, std::nullopt) << detail(c).second;
  c.position_m[2] = 230.0;
  EXPECT_EQ(detail(c).first, RejectReason::kOffTerrain);
  EXPECT_NE(detail(c).second.find("z = 230 m is outside [0, 220] m"), std::string::npos)
      << detail(c).second;
  c = sample::Construct();
  c.position_m[0] = 1000.5;
  EXPECT_NE(detail(c).second.find("x = 1000.5 m is outside [0, 1000] m"), std::string::npos)
      << detail(c).second;
  // The same z would be on a square 1000 m terrain: the bounds are not swapped.
  c = sample::Construct();
  c.position_m[0] = 219.0;
  c.position_m[2] = 900.0;
  EXPECT_EQ(detail(c).first, RejectReason::kOffTerrain);
  ValidationContext tall = wide;
  std::swap(tall.terrain_size_x_m, tall.terrain_size_z_m);
  EXPECT_EQ(ReasonFor(c, tall), std::nullopt);
  auto d = sample::DitchConstruct();  // points up to z = 140
  EXPECT_EQ(detail(d).first, std::nullopt) << detail(d).second;
  d.points[2].z_m = 221;
  EXPECT_NE(detail(d).second.find("points[2].z_m = 221 m is outside [0, 220] m"), std::string::npos)
      << detail(d).second;
  auto v = sample::VehicleState();  // at x 500.25, z 250.75
  EXPECT_NE(detail(v).second.find("at z = 250.75 m is outside [0, 220] m"), std::string::npos)
      << detail(v).second;
  EXPECT_EQ(ReasonFor(v, tall), RejectReason::kOffTerrain);  // x 500.25 > 220
  tall.terrain_size_z_m = 2000.0;
  tall.terrain_size_x_m = 600.0;
  EXPECT_EQ(ReasonFor(v, tall), std::nullopt);
}

TEST(Validation, PointFeaturesPassAndTheirBadPointsAreRefusedByName) {
  EXPECT_EQ(ReasonFor(sample::DitchConstruct()), std::nullopt);
  auto flood = ToConstruct(sample::Flood());
  sample::StampHeader(flood);
  EXPECT_EQ(ReasonFor(flood), std::nullopt);
  auto detail = [](const dtpdu::construct_t& c) {
    dtpdu::construct_t out;
    auto r = DecodeAndValidate(std::span<const uint8_t>(EncodePdu(c)), Context(), out);
    return r ? std::pair{r->reason, r->detail} : std::pair{RejectReason::kBadField, std::string()};
  };
  auto c = sample::DitchConstruct();
  c.points[2].z_m = -1;
  EXPECT_EQ(detail(c).first, RejectReason::kOffTerrain);
  EXPECT_NE(detail(c).second.find("points[2].z_m"), std::string::npos) << detail(c).second;
  c = sample::DitchConstruct();
  c.points[1].width_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(detail(c).first, RejectReason::kNotFinite);
  EXPECT_NE(detail(c).second.find("points[1].width_m"), std::string::npos);
  c = sample::DitchConstruct();
  c.points[1].x_m = 99;  // back on itself
  EXPECT_EQ(detail(c).first, RejectReason::kOutOfRange);
  EXPECT_NE(detail(c).second.find("points[1]: the line turns by"), std::string::npos)
      << detail(c).second;
  c = sample::Construct();  // a crater
  c.num_points = 1;
  c.points.push_back({100, 200, 0, 0});
  EXPECT_EQ(detail(c).first, RejectReason::kOutOfRange);
  EXPECT_NE(detail(c).second.find("cannot carry points"), std::string::npos);
}

TEST(Validation, ADitchOfTheMostPointsFitsAPduWithItsTrailer) {
  auto c = sample::DitchConstruct();
  c.num_points = static_cast<int16_t>(kMaxFeaturePoints);
  c.points.resize(kMaxFeaturePoints);
  for (int i = 0; i < kMaxFeaturePoints; ++i) {
    c.points[static_cast<size_t>(i)] = {100.0 + 20 * i, 100, 2, 6};
  }
  EXPECT_EQ(ReasonFor(c), std::nullopt);
  EXPECT_LE(EncodePdu(c).size() + kAuthTrailerBytes, kMaxPduBytes);
}

TEST(Validation, BadFields) {
  auto c = sample::Construct();
  c.feature_number = 0;
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  c = sample::Construct();
  c.feature_number = kMaxSerial + 1;
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  c = sample::Construct();
  c.sender_seq = 0;
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  c = sample::Construct();
  c.created_by.host = 99;  // a Construct is made by the feature's origin
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  c = sample::Construct();
  c.num_vertex_edits = 65;
  c.vertex_edits.resize(65);
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  auto u = sample::Update();
  u.status = 2;
  EXPECT_EQ(ReasonFor(u), RejectReason::kBadField);
  u = sample::Update();
  u.lamport = 0;
  EXPECT_EQ(ReasonFor(u), RejectReason::kBadField);
  auto d = sample::Destruct();
  d.change_seq = 0;
  EXPECT_EQ(ReasonFor(d), RejectReason::kBadField);
  auto m = sample::MaxFeature();
  m.role = 3;
  EXPECT_EQ(ReasonFor(m), RejectReason::kBadField);
  m = sample::MaxFeature();
  m.max_feature_number = -1;
  EXPECT_EQ(ReasonFor(m), RejectReason::kBadField);
  m = sample::MaxFeature();
  m.max_change_seq = kMaxSerial + 1;
  EXPECT_EQ(ReasonFor(m), RejectReason::kBadField);
  m = sample::MaxFeature();
  m.lamport = -5;
  EXPECT_EQ(ReasonFor(m), RejectReason::kBadField);
  auto p = sample::Playback();
  p.range_kind = 2;
  EXPECT_EQ(ReasonFor(p), RejectReason::kBadField);
  p = sample::Playback();
  p.range_complete = 1;  // only a response can complete a range
  EXPECT_EQ(ReasonFor(p), RejectReason::kBadField);
  p.is_response = 1;
  EXPECT_EQ(ReasonFor(p), std::nullopt);
  p = sample::Playback();
  p.start = 0;
  EXPECT_EQ(ReasonFor(p), RejectReason::kBadField);
}

TEST(Validation, InvertedPlaybackRange) {
  auto p = sample::Playback();
  p.start = 21;
  p.end = 20;
  EXPECT_EQ(ReasonFor(p), RejectReason::kInvertedRange);
  p.start = 20;
  EXPECT_EQ(ReasonFor(p), std::nullopt);
}

TEST(Validation, HugePlaybackRange) {
  auto p = sample::Playback();
  p.start = 1;
  p.end = kMaxPlaybackSpan;
  EXPECT_EQ(ReasonFor(p), std::nullopt);
  p.end = kMaxPlaybackSpan + 1;
  EXPECT_EQ(ReasonFor(p), RejectReason::kHugeRange);
  p.end = kMaxSerial;
  EXPECT_EQ(ReasonFor(p), RejectReason::kHugeRange);
}

TEST(Validation, AntiEntropyFieldsEachKindDoesNotUseAreZero) {
  auto a = sample::AntiEntropySummary();
  a.kind = 5;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.role = 4;  // 3 is an observer's
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.start = 1;
  a.end = 1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);  // a summary has no range
  a = sample::AntiEntropySummary();
  a.target = ToPdu({1, 1});
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.entries[0].seq = -1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a.entries[0].seq = kMaxSerial + 1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.entries[0].seq = 0;  // changes held beyond a gap only: a prefix of none, hashed 0
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a.entries[0].prefix_hash = 0;
  EXPECT_EQ(ReasonFor(a), std::nullopt);
  a.entries[0].max_held = 0;  // holds nothing: no entry
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.entries[1].max_held = a.entries[1].seq - 1;  // below the gap-free point
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a.entries[1].max_held = kMaxSerial + 1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.entries.resize(kMaxSummaryAuthors + 1, a.entries[0]);
  a.num_entries = static_cast<int16_t>(a.entries.size());
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a.entries.resize(kMaxSummaryAuthors);
  a.num_entries = static_cast<int16_t>(a.entries.size());
  // The fullest summary fits one datagram, signed.
  EXPECT_LE(EncodePdu(a).size() + kAuthTrailerBytes, kMaxPduBytes);
  EXPECT_EQ(ReasonFor(a), std::nullopt);
  EXPECT_LE(EncodePdu(a).size(), kMaxPduBytes);
  a = sample::AntiEntropySummary();
  a.hashes = {1};  // only answers and copies carry hashes
  a.num_hashes = 1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);
  a = sample::AntiEntropySummary();
  a.exchange = 1;
  EXPECT_EQ(ReasonFor(a), RejectReason::kBadField);

  auto h = sample::AntiEntropyHashes();
  h.hashes.pop_back();
  h.num_hashes = static_cast<int16_t>(h.hashes.size());
  EXPECT_EQ(ReasonFor(h), RejectReason::kBadField);  // not one hash per bucket
  h.hashes.clear();
  h.num_hashes = 0;
  EXPECT_EQ(ReasonFor(h), std::nullopt);  // "I do not hold the whole range"
  h = sample::AntiEntropyHashes();
  h.kind = static_cast<uint8_t>(AntiEntropyKind::kHashRequest);
  EXPECT_EQ(ReasonFor(h), RejectReason::kBadField);  // a request carries no hashes
  h.hashes.clear();
  h.num_hashes = 0;
  EXPECT_EQ(ReasonFor(h), std::nullopt);
  h.start = 0;
  EXPECT_EQ(ReasonFor(h), RejectReason::kBadField);
  h.start = 301;
  EXPECT_EQ(ReasonFor(h), RejectReason::kInvertedRange);
  h.start = 1;
  h.end = kMaxSerial;  // any range can be hashed: the buckets cost the same
  EXPECT_EQ(ReasonFor(h), std::nullopt);

  auto c = sample::AntiEntropyCopies();
  c.hashes = {4};  // one hash per sequence of the range
  c.num_hashes = 1;
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);
  c = sample::AntiEntropyCopies();
  c.end = c.start + kMaxCopySpan - 1;
  c.hashes.resize(static_cast<size_t>(kMaxCopySpan), 1);
  c.num_hashes = static_cast<int16_t>(c.hashes.size());
  EXPECT_EQ(ReasonFor(c), std::nullopt);
  c.end = c.start + kMaxCopySpan;
  EXPECT_EQ(ReasonFor(c), RejectReason::kHugeRange);
  c = sample::AntiEntropyCopies();
  c.kind = static_cast<uint8_t>(AntiEntropyKind::kCopyRequest);
  EXPECT_EQ(ReasonFor(c), RejectReason::kBadField);  // a request carries no hashes
  c.hashes.clear();
  c.num_hashes = 0;
  c.exchange = 1;
  EXPECT_EQ(ReasonFor(c), std::nullopt);
}

TEST(Validation, AntiEntropyBucketsCoverTheRangeExactlyOnce) {
  for (auto [start, end] : {std::pair<int64_t, int64_t>{1, 1},
                            {1, 31},
                            {1, 32},
                            {1, 33},
                            {7, 100000},
                            {1, kMaxSerial}}) {
    const int64_t k = AntiEntropyBucketCount(start, end);
    EXPECT_EQ(k, std::min<int64_t>(kAntiEntropyBuckets, end - start + 1));
    int64_t next = start;
    for (int64_t i = 0; i < k; ++i) {
      auto [lo, hi] = HashBucket(start, end, i);
      EXPECT_EQ(lo, next) << start << ".." << end << " bucket " << i;
      EXPECT_GE(hi, lo);
      next = hi + 1;
    }
    EXPECT_EQ(next, end + 1);
  }
}

TEST(Validation, EveryReasonHasItsOwnName) {
  std::set<std::string_view> names;
  for (size_t i = 0; i < kRejectReasonCount; ++i) {
    names.insert(RejectReasonName(static_cast<RejectReason>(i)));
  }
  EXPECT_EQ(names.size(), kRejectReasonCount);
  EXPECT_EQ(names.count("unknown"), 0u);
}

TEST(RejectLog, CountsEveryRejectionButLogsAtMostOncePerIntervalPerReason) {
  RejectLog log(std::chrono::milliseconds(1000));
  const RejectLog::Clock::time_point t0{};
  const Rejection trunc{RejectReason::kTruncated, "x"};
  const Rejection foreign{RejectReason::kForeignExercise, "y"};
  EXPECT_TRUE(log.Record(PduType::kConstruct, trunc, t0));
  EXPECT_TRUE(log.Record(PduType::kConstruct, foreign, t0));
  for (int i = 1; i <= 100; ++i) {
    EXPECT_FALSE(log.Record(PduType::kConstruct, trunc, t0 + std::chrono::milliseconds(i)));
  }
  EXPECT_TRUE(log.Record(PduType::kUpdate, trunc, t0 + std::chrono::milliseconds(1000)));
  EXPECT_EQ(log.counters().count(RejectReason::kTruncated), 102u);
  EXPECT_EQ(log.counters().count(RejectReason::kForeignExercise), 1u);
  EXPECT_EQ(log.counters().total(), 103u);
}

}  // namespace
}  // namespace dt
