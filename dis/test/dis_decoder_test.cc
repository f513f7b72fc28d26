// Bad DIS input is refused whole, with a reason that names the values, and counted.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <set>

#include "dis/dis_codec.h"
#include "dis/test/golden_pdus.h"

namespace dt::dis {
namespace {

std::vector<uint8_t> GoldenEs() { return Encode(testing::GoldenEntityState()); }

void PutU64(std::vector<uint8_t>& b, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = static_cast<uint8_t>(v >> (56 - 8 * i));
}
void PutU32(std::vector<uint8_t>& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}
void PutLength(std::vector<uint8_t>& b, size_t length) {
  b[8] = static_cast<uint8_t>(length >> 8);
  b[9] = static_cast<uint8_t>(length);
}

DecodeFailure FailureOf(const std::vector<uint8_t>& bytes) {
  const DecodeResult r = DecodePdu(bytes, uint8_t{5});
  EXPECT_FALSE(r.ok());
  return r.ok() ? DecodeFailure::kBadField : r.error().failure;
}

TEST(DisDecoder, AcceptsTheGoldenPdusOfItsExercise) {
  Decoder d(5);
  EXPECT_TRUE(d.Decode(GoldenEs()).ok());
  EXPECT_TRUE(d.Decode(Encode(testing::GoldenPointObjectState())).ok());
  EXPECT_TRUE(d.Decode(Encode(testing::GoldenLinearObjectState())).ok());
  EXPECT_EQ(d.counters().entity_state, 1u);
  EXPECT_EQ(d.counters().point_object_state, 1u);
  EXPECT_EQ(d.counters().linear_object_state, 1u);
  EXPECT_EQ(d.counters().rejected_total(), 0u);
}

TEST(DisDecoder, EveryTruncationOfEveryPduIsRefused) {
  for (const std::vector<uint8_t>& whole : {GoldenEs(), Encode(testing::GoldenPointObjectState()),
                                            Encode(testing::GoldenLinearObjectState())}) {
    Decoder d(5);
    for (size_t n = 0; n < whole.size(); ++n) {
      const std::vector<uint8_t> cut(whole.begin(), whole.begin() + static_cast<long>(n));
      const DecodeResult r = d.Decode(cut);
      ASSERT_FALSE(r.ok()) << n << " bytes";
      // Under a header it is too short; past it, the length field no longer matches.
      EXPECT_EQ(r.error().failure,
                n < kHeaderSize ? DecodeFailure::kTooShort : DecodeFailure::kLengthMismatch)
          << n << " bytes: " << r.error().message;
    }
    EXPECT_EQ(d.counters().rejected_total(), whole.size());
    EXPECT_EQ(d.counters().entity_state + d.counters().point_object_state +
                  d.counters().linear_object_state,
              0u);
  }
}

TEST(DisDecoder, ShortPduWithAMatchingLengthFieldIsTooShort) {
  std::vector<uint8_t> b = GoldenEs();
  b.resize(100);
  PutLength(b, 100);
  EXPECT_EQ(FailureOf(b), DecodeFailure::kTooShort);
  std::vector<uint8_t> point = Encode(testing::GoldenPointObjectState());
  point.resize(60);
  PutLength(point, 60);
  EXPECT_EQ(FailureOf(point), DecodeFailure::kTooShort);
}

TEST(DisDecoder, LengthFieldDifferentFromTheDatagramIsRefused) {
  std::vector<uint8_t> b = GoldenEs();
  PutLength(b, 143);
  const DecodeResult r = DecodePdu(b, uint8_t{5});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().failure, DecodeFailure::kLengthMismatch);
  EXPECT_NE(r.error().message.find("143"), std::string::npos) << r.error().message;
  b = GoldenEs();
  b.push_back(0);  // one trailing byte
  EXPECT_EQ(FailureOf(b), DecodeFailure::kLengthMismatch);
}

TEST(DisDecoder, RecordCountsMustMatchTheLength) {
  std::vector<uint8_t> es = GoldenEs();
  es[19] = 1;  // claims a variable parameter it does not carry
  EXPECT_EQ(FailureOf(es), DecodeFailure::kLengthMismatch);
  std::vector<uint8_t> linear = Encode(testing::GoldenLinearObjectState());
  linear[27] = 2;  // claims two segments, carries one
  EXPECT_EQ(FailureOf(linear), DecodeFailure::kLengthMismatch);
  linear[27] = 0;
  EXPECT_EQ(FailureOf(linear), DecodeFailure::kLengthMismatch);
}

TEST(DisDecoder, UnknownPduTypesAreRefusedAndNamed) {
  for (int type : {0, 2, 3, 41, 42, 45, 255}) {
    std::vector<uint8_t> b = GoldenEs();
    b[2] = static_cast<uint8_t>(type);
    const DecodeResult r = DecodePdu(b, uint8_t{5});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().failure, DecodeFailure::kUnsupportedPduType);
    EXPECT_NE(r.error().message.find(std::to_string(type)), std::string::npos);
  }
}

TEST(DisDecoder, ForeignExerciseIsRefusedBeforeItsTypeIsLookedAt) {
  std::vector<uint8_t> b = GoldenEs();
  b[1] = 6;
  EXPECT_EQ(FailureOf(b), DecodeFailure::kForeignExercise);
  b[2] = 200;  // even of an unknown type
  EXPECT_EQ(FailureOf(b), DecodeFailure::kForeignExercise);
  EXPECT_TRUE(DecodePdu(GoldenEs()).ok()) << "without an exercise filter every exercise is read";
}

TEST(DisDecoder, NonFiniteFieldsAreRefusedByName) {
  const uint64_t nan64 = std::bit_cast<uint64_t>(std::numeric_limits<double>::quiet_NaN());
  const uint32_t inf32 = std::bit_cast<uint32_t>(std::numeric_limits<float>::infinity());
  std::vector<uint8_t> b = GoldenEs();
  PutU64(b, 56, nan64);  // location y
  DecodeResult r = DecodePdu(b, uint8_t{5});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().failure, DecodeFailure::kNonFinite);
  EXPECT_NE(r.error().message.find("location y"), std::string::npos) << r.error().message;
  for (size_t at : {36u, 72u, 80u, 104u, 124u}) {  // velocity, psi, phi, acceleration, angular
    b = GoldenEs();
    PutU32(b, at, inf32);
    EXPECT_EQ(FailureOf(b), DecodeFailure::kNonFinite) << "offset " << at;
  }
  std::vector<uint8_t> point = Encode(testing::GoldenPointObjectState());
  PutU64(point, 32, nan64);  // location x
  EXPECT_EQ(FailureOf(point), DecodeFailure::kNonFinite);
  std::vector<uint8_t> linear = Encode(testing::GoldenLinearObjectState());
  PutU32(linear, 40 + 44, inf32);  // segment length
  r = DecodePdu(linear, uint8_t{5});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().failure, DecodeFailure::kNonFinite);
  EXPECT_NE(r.error().message.find("segment length"), std::string::npos) << r.error().message;
}

TEST(DisDecoder, VersionsAndFamilies) {
  std::vector<uint8_t> b = GoldenEs();
  b[0] = 6;  // DIS 6 Entity State has the same layout
  EXPECT_TRUE(DecodePdu(b, uint8_t{5}).ok());
  b[0] = 5;
  EXPECT_EQ(FailureOf(b), DecodeFailure::kUnsupportedVersion);
  std::vector<uint8_t> linear = Encode(testing::GoldenLinearObjectState());
  linear[0] = 6;  // the DIS 6 segment layout differs
  EXPECT_EQ(FailureOf(linear), DecodeFailure::kUnsupportedVersion);
  b = GoldenEs();
  b[3] = 9;
  EXPECT_EQ(FailureOf(b), DecodeFailure::kFamilyMismatch);
}

TEST(DisDecoder, UndefinedDeadReckoningAlgorithmIsABadField) {
  std::vector<uint8_t> b = GoldenEs();
  b[88] = 10;
  EXPECT_EQ(FailureOf(b), DecodeFailure::kBadField);
}

TEST(DisDecoder, CountsEachReasonApart) {
  Decoder d(5);
  std::vector<uint8_t> foreign = GoldenEs();
  foreign[1] = 9;
  std::vector<uint8_t> unknown = GoldenEs();
  unknown[2] = 2;
  (void)d.Decode(foreign);
  (void)d.Decode(foreign);
  (void)d.Decode(unknown);
  (void)d.Decode(std::vector<uint8_t>(3, 0));
  (void)d.Decode(GoldenEs());
  EXPECT_EQ(d.counters().rejected_for(DecodeFailure::kForeignExercise), 2u);
  EXPECT_EQ(d.counters().rejected_for(DecodeFailure::kUnsupportedPduType), 1u);
  EXPECT_EQ(d.counters().rejected_for(DecodeFailure::kTooShort), 1u);
  EXPECT_EQ(d.counters().rejected_total(), 4u);
  EXPECT_EQ(d.counters().entity_state, 1u);
}

TEST(DisDecoder, OversizedDatagramIsTooLong) {
  std::vector<uint8_t> b = GoldenEs();
  b.resize(kMaxPduSize + 1);
  EXPECT_EQ(FailureOf(b), DecodeFailure::kTooLong);
}

TEST(DisDecoder, FailureNamesAreDistinct) {
  std::set<std::string_view> names;
  for (size_t i = 0; i < kDecodeFailureCount; ++i) {
    names.insert(DecodeFailureName(static_cast<DecodeFailure>(i)));
  }
  EXPECT_EQ(names.size(), kDecodeFailureCount);
}

}  // namespace
}  // namespace dt::dis
