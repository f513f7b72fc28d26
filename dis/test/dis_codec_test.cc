// Golden bytes of each PDU (docs/dis.md's layouts), and round trips through encode and decode.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "dis/dis_codec.h"
#include "dis/test/golden_pdus.h"

namespace dt::dis {
namespace {

using testing::FromHex;

template <typename T>
T DecodeAs(const std::vector<uint8_t>& bytes) {
  const DecodeResult r = DecodePdu(bytes);
  if (!r.ok()) ADD_FAILURE() << r.error().message;
  EXPECT_TRUE(std::holds_alternative<T>(r.pdu()));
  return std::get<T>(r.pdu());
}

TEST(DisCodec, EntityStateMatchesGoldenBytes) {
  const std::vector<uint8_t> golden = FromHex(testing::kGoldenEntityStateHex);
  ASSERT_EQ(golden.size(), kEntityStateSize);
  EXPECT_EQ(Encode(testing::GoldenEntityState()), golden);
  EntityStatePdu expected = testing::GoldenEntityState();
  expected.header.pdu_type = 1;
  expected.header.protocol_family = 1;
  expected.header.length = 144;
  EXPECT_EQ(DecodeAs<EntityStatePdu>(golden), expected);
}

TEST(DisCodec, PointObjectStateMatchesGoldenBytes) {
  const std::vector<uint8_t> golden = FromHex(testing::kGoldenPointObjectStateHex);
  ASSERT_EQ(golden.size(), kPointObjectStateSize);
  EXPECT_EQ(Encode(testing::GoldenPointObjectState()), golden);
  PointObjectStatePdu expected = testing::GoldenPointObjectState();
  expected.header.pdu_type = 43;
  expected.header.protocol_family = 9;
  expected.header.length = 88;
  EXPECT_EQ(DecodeAs<PointObjectStatePdu>(golden), expected);
}

TEST(DisCodec, LinearObjectStateMatchesGoldenBytes) {
  const std::vector<uint8_t> golden = FromHex(testing::kGoldenLinearObjectStateHex);
  ASSERT_EQ(golden.size(), kLinearObjectStateSize + kLinearSegmentSize);
  EXPECT_EQ(Encode(testing::GoldenLinearObjectState()), golden);
  LinearObjectStatePdu expected = testing::GoldenLinearObjectState();
  expected.header.pdu_type = 44;
  expected.header.protocol_family = 9;
  expected.header.length = 104;
  EXPECT_EQ(DecodeAs<LinearObjectStatePdu>(golden), expected);
}

TEST(DisCodec, EntityStateWithVariableParametersRoundTrips) {
  EntityStatePdu p = testing::GoldenEntityState();
  for (uint8_t i = 0; i < 3; ++i) {
    VariableParameter v;
    v.record_type = i;
    v.data.fill(static_cast<uint8_t>(0xA0 + i));
    p.variable_parameters.push_back(v);
  }
  const std::vector<uint8_t> bytes = Encode(p);
  ASSERT_EQ(bytes.size(), kEntityStateSize + 3 * kVariableParameterSize);
  EXPECT_EQ(bytes[19], 3);
  EXPECT_EQ(bytes[144], 0);
  EXPECT_EQ(bytes[145], 0xA0);
  const auto back = DecodeAs<EntityStatePdu>(bytes);
  EXPECT_EQ(back.variable_parameters, p.variable_parameters);
}

TEST(DisCodec, LinearObjectWithManySegmentsRoundTrips) {
  LinearObjectStatePdu p = testing::GoldenLinearObjectState();
  for (uint8_t i = 2; i <= 5; ++i) {
    LinearSegment s = p.segments[0];
    s.segment_number = i;
    s.length_m = 10.0f * i;
    p.segments.push_back(s);
  }
  const std::vector<uint8_t> bytes = Encode(p);
  ASSERT_EQ(bytes.size(), kLinearObjectStateSize + 5 * kLinearSegmentSize);
  const auto back = DecodeAs<LinearObjectStatePdu>(bytes);
  ASSERT_EQ(back.segments.size(), 5u);
  EXPECT_EQ(back.segments, p.segments);
}

TEST(DisCodec, EncodeRefusesNonFiniteFields) {
  EntityStatePdu es = testing::GoldenEntityState();
  es.location.y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Encode(es), std::invalid_argument);
  es = testing::GoldenEntityState();
  es.dead_reckoning.angular_velocity.z = std::numeric_limits<float>::infinity();
  EXPECT_THROW(Encode(es), std::invalid_argument);
  PointObjectStatePdu point = testing::GoldenPointObjectState();
  point.orientation.phi = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(Encode(point), std::invalid_argument);
  LinearObjectStatePdu linear = testing::GoldenLinearObjectState();
  linear.segments[0].width_m = -std::numeric_limits<float>::infinity();
  EXPECT_THROW(Encode(linear), std::invalid_argument);
}

TEST(DisCodec, EncodeRefusesMoreThan255Records) {
  EntityStatePdu es = testing::GoldenEntityState();
  es.variable_parameters.resize(256);
  EXPECT_THROW(Encode(es), std::invalid_argument);
  LinearObjectStatePdu linear = testing::GoldenLinearObjectState();
  linear.segments.resize(256, linear.segments[0]);
  EXPECT_THROW(Encode(linear), std::invalid_argument);
}

}  // namespace
}  // namespace dt::dis
