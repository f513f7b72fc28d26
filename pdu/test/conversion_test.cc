// Tests feature <-> PDU conversion: identity bit for bit, and refusal of unrepresentable fields.
#include "pdu/conversion.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "pdu/pdu_type.h"
#include "terrain/bytes.h"

namespace dt {
namespace {

std::vector<uint8_t> Bits(const FeatureParams& p) {
  ByteWriter w;
  EncodeFeatureParams(p, w);
  return w.bytes();
}

// Random features of every type whose doubles use all 64 bits (not just "nice" values).
FeaturePdu RandomFeature(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(0.0, 5000.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  FeaturePdu f;
  f.id = FeatureId{static_cast<uint16_t>(rng()), static_cast<uint16_t>(rng()),
                   static_cast<uint32_t>(rng() % kMaxSerial) + 1};
  f.change = ChangeStamp{NodeAddress{static_cast<uint16_t>(rng()), static_cast<uint16_t>(rng())},
                         static_cast<uint32_t>(rng() % kMaxSerial) + 1, (rng() >> 2) + 1};
  switch (rng() % 3) {
    case 0: {
      f.params = FeatureParams::Crater(pos(rng), pos(rng), 0.5 + 100 * unit(rng));
      for (uint8_t spoke = 0; spoke < 16; ++spoke) {
        if (rng() % 4 == 0) f.params.vertex_edits.push_back({spoke, 2, unit(rng) - 0.5});
      }
      break;
    }
    case 1:
      f.params = FeatureParams::Berm(pos(rng), pos(rng), 6.28 * unit(rng), 1 + 500 * unit(rng),
                                     1 + 20 * unit(rng), 0.1 + 10 * unit(rng), Material::kDirt);
      break;
    default:
      f.params = FeatureParams::Bridge(pos(rng), pos(rng), -3.1 * unit(rng), 1 + 10 * unit(rng),
                                       5 + 30 * unit(rng), 10 + 100 * unit(rng), 5 + 30 * unit(rng),
                                       2 + 5 * unit(rng), 2 + 5 * unit(rng));
      f.params.status = rng() % 2 ? BridgeStatus::kDestroyed : BridgeStatus::kIntact;
  }
  return f;
}

TEST(Conversion, FeatureToConstructToFeatureIsTheIdentityBitForBit) {
  std::mt19937_64 rng(12345);
  for (int i = 0; i < 2000; ++i) {
    const FeaturePdu f = RandomFeature(rng);
    auto back = FromConstruct(ToConstruct(f));
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back.value(), f);
    EXPECT_EQ(Bits(back.value().params), Bits(f.params));
    auto up = FromUpdate(ToUpdate(f));
    ASSERT_TRUE(up.ok()) << up.error().message;
    EXPECT_EQ(Bits(up.value().params), Bits(f.params));
  }
}

TEST(Conversion, SurvivesLcmEncodingBitForBit) {
  std::mt19937_64 rng(777);
  for (int i = 0; i < 500; ++i) {
    const FeaturePdu f = RandomFeature(rng);
    dtpdu::construct_t pdu = ToConstruct(f);
    std::vector<uint8_t> bytes(static_cast<size_t>(pdu.getEncodedSize()));
    ASSERT_EQ(pdu.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
              static_cast<int>(bytes.size()));
    dtpdu::construct_t decoded;
    ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
              static_cast<int>(bytes.size()));
    auto back = FromConstruct(decoded);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(Bits(back.value().params), Bits(f.params));
  }
}

TEST(Conversion, KeepsSignedZeroAndSubnormals) {
  FeaturePdu f;
  f.id = {1, 2, 3};
  f.change = {{1, 2}, 1, 1};
  f.params =
      FeatureParams::Berm(std::numeric_limits<double>::denorm_min(), 10.0, -0.0, 10.0, 2.0, 1.0);
  auto back = FromConstruct(ToConstruct(f));
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(std::signbit(back.value().params.direction_rad));
  EXPECT_EQ(Bits(back.value().params), Bits(f.params));
}

TEST(Conversion, CarriesFullSixteenBitAddressesAndThirtyTwoBitNumbers) {
  FeaturePdu f;
  f.id = {65535, 40000, 4294967295u};
  f.change = {{65535, 65534}, 4294967295u, 1};
  f.params = FeatureParams::Crater(1, 1, 1);
  const auto pdu = ToConstruct(f);
  EXPECT_EQ(pdu.feature_number, 4294967295);
  auto back = FromConstruct(pdu);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value().id, f.id);
  EXPECT_EQ(back.value().change, f.change);
}

TEST(Conversion, DestructRoundTrips) {
  DestructPdu d{{7, 8, 9}, FeatureType::kBridge, {{3, 4}, 12, 99}};
  auto back = FromDestruct(ToDestruct(d));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value(), d);
}

TEST(Conversion, RefusesUnrepresentableFields) {
  FeaturePdu f;
  f.id = {1, 1, 1};
  f.change = {{1, 1}, 1, 1};
  f.params = FeatureParams::Crater(5, 5, 2);
  const dtpdu::construct_t good = ToConstruct(f);
  ASSERT_TRUE(FromConstruct(good).ok());

  auto expect_refused = [&](auto mutate, const char* word) {
    dtpdu::construct_t pdu = good;
    mutate(pdu);
    auto r = FromConstruct(pdu);
    ASSERT_FALSE(r.ok()) << word;
    EXPECT_NE(r.error().message.find(word), std::string::npos) << r.error().message;
  };
  expect_refused([](auto& p) { p.feature_number = 0; }, "feature_number");
  expect_refused([](auto& p) { p.feature_number = kMaxSerial + 1; }, "feature_number");
  expect_refused([](auto& p) { p.change_seq = -1; }, "change_seq");
  expect_refused([](auto& p) { p.lamport = 0; }, "lamport");
  expect_refused([](auto& p) { p.feature_type = 4; }, "feature type");
  expect_refused([](auto& p) { p.material = kMaterialCount; }, "material");
  expect_refused([](auto& p) { p.status = 2; }, "status");
  expect_refused([](auto& p) { p.num_vertex_edits = 1; }, "num_vertex_edits");
}

}  // namespace
}  // namespace dt
