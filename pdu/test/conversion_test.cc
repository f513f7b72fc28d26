// Tests feature <-> PDU conversion: identity bit for bit, and refusal of unrepresentable fields.
#include "pdu/conversion.h"

#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "base/bytes.h"
#include "pdu/pdu_type.h"

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
  auto point = [&](double x, double z, double h, double w) { return FeaturePoint{x, z, h, w}; };
  switch (rng() % 6) {
    case 3: {
      const double x = pos(rng), z = pos(rng), run = 0.5 + unit(rng);
      f.params = FeatureParams::Ditch({point(x, z, 1 + unit(rng), 3 + unit(rng)),
                                       point(x + 10 + unit(rng), z + unit(rng), 2, 4),
                                       point(x + 20, z + 10 * unit(rng), 1 + unit(rng), 5)},
                                      run, rng() % 2 ? 1 + unit(rng) : 0.0, 0.0, Material::kDirt);
      if (f.params.height_m[1] != 0.0) f.params.length_m[1] = 1 + unit(rng);
      break;
    }
    case 4: {
      const double x = pos(rng), z = pos(rng);
      f.params = FeatureParams::BermLine(
          {point(x, z, 1 + unit(rng), 3 + unit(rng)), point(x + 5 * unit(rng) + 1, z, 2, 4)});
      break;
    }
    case 5: {
      const double x = pos(rng), z = pos(rng);
      f.params =
          FeatureParams::Area({point(x, z, 0, 0), point(x + 30 * unit(rng) + 1, z, 0, 0),
                               point(x, z + 30 * unit(rng) + 1, 0, 0)},
                              rng() % 2 ? Material::kWater : Material::kOil, 100 * unit(rng));
      break;
    }
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
  expect_refused([](auto& p) { p.feature_type = 8; }, "feature type");
  expect_refused([](auto& p) { p.feature_type = 7; }, "travels only in EarthMove PDUs");
  expect_refused([](auto& p) { p.material = kMaterialCount; }, "material");
  expect_refused([](auto& p) { p.status = 2; }, "status");
  expect_refused([](auto& p) { p.num_vertex_edits = 1; }, "num_vertex_edits");
  expect_refused([](auto& p) { p.num_points = 1; }, "num_points");
  expect_refused([](auto& p) { p.num_points = -1; }, "num_points");
}

TEST(Conversion, EveryTypeOccursInTheRandomFeatures) {
  std::mt19937_64 rng(12345);
  std::set<FeatureType> seen;
  for (int i = 0; i < 200; ++i) seen.insert(RandomFeature(rng).params.type);
  EXPECT_EQ(seen.size(), 6u);
}

}  // namespace
}  // namespace dt
