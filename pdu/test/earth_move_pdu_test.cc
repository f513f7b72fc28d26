// The EarthMove PDU: conversion both ways, validation naming the field, and its largest size.
#include <string>

#include <gtest/gtest.h>

#include "pdu/auth_trailer.h"
#include "pdu/conversion.h"
#include "pdu/test/sample_pdus.h"
#include "pdu/validation.h"

namespace dt {
namespace {

void ExpectRejected(const dtpdu::earth_move_t& pdu, RejectReason reason, const std::string& detail,
                    ValidationContext ctx = sample::Context()) {
  const auto r = Validate(pdu, ctx);
  ASSERT_TRUE(r.has_value()) << "accepted; expected " << detail;
  EXPECT_EQ(r->reason, reason) << r->detail;
  EXPECT_NE(r->detail.find(detail), std::string::npos) << r->detail;
}

TEST(EarthMovePduTest, ConvertsBothWaysBitForBit) {
  const FeaturePdu f = sample::EarthMove();
  const auto pdu = ToEarthMove(f);
  EXPECT_EQ(pdu.first_post_i, 40);
  EXPECT_EQ(pdu.first_post_j, 50);
  EXPECT_EQ(pdu.columns, 3);
  EXPECT_EQ(pdu.rows, 3);
  EXPECT_EQ(pdu.num_mask_bytes, 2);
  EXPECT_EQ(pdu.changed_mask[0], 0b11000111);  // posts 0, 1, 2 and 6, 7 of the 3 x 3 square
  EXPECT_EQ(pdu.changed_mask[1], 0b00000001);  // post 8
  auto back = FromEarthMove(pdu);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), f);
  EXPECT_FALSE(Validate(sample::EarthMovePdu(), sample::Context()).has_value());
  // Through its encoding too.
  dtpdu::earth_move_t decoded;
  EXPECT_FALSE(DecodeAndValidate(EncodePdu(sample::EarthMovePdu()), sample::Context(), decoded));
  EXPECT_EQ(FromEarthMove(decoded).value(), f);
}

TEST(EarthMovePduTest, BadFieldsAreRejectedNamingThem) {
  auto p = sample::EarthMovePdu();
  p.delta_mm[2] = 0;
  ExpectRejected(p, RejectReason::kOutOfRange, "post_deltas[2].delta_mm = 0");
  p = sample::EarthMovePdu();
  p.delta_mm[0] = 12000;
  ExpectRejected(p, RejectReason::kOutOfRange, "delta_mm = 12000");
  p = sample::EarthMovePdu();
  p.changed_mask[0] |= 0x08;  // a fourth post in the first row of deltas
  ExpectRejected(p, RejectReason::kBadField, "more posts than num_posts = 6");
  p = sample::EarthMovePdu();
  p.changed_mask[1] |= 0x02;  // past the 9 posts of the square
  ExpectRejected(p, RejectReason::kBadField, "bits past the 9 posts");
  p = sample::EarthMovePdu();
  p.num_posts = 5;
  ExpectRejected(p, RejectReason::kBadField, "num_posts = 5");
  p = sample::EarthMovePdu();
  p.columns = 49;
  ExpectRejected(p, RejectReason::kBadField, "rectangle 49 x 3 posts");
  p = sample::EarthMovePdu();
  p.num_mask_bytes = 1;
  ExpectRejected(p, RejectReason::kBadField, "num_mask_bytes = 1");
  p = sample::EarthMovePdu();
  p.first_post_j = -2;
  ExpectRejected(p, RejectReason::kBadField, "first post (40, -2)");
  p = sample::EarthMovePdu();
  p.moved_by.host = 9;
  ExpectRejected(p, RejectReason::kBadField, "only the origin makes an earth move");
  p = sample::EarthMovePdu();
  p.change_seq = 0;
  ExpectRejected(p, RejectReason::kBadField, "change_seq = 0");
  // Posts off this exercise's grid.
  ValidationContext small = sample::Context();
  small.terrain_posts_x = small.terrain_posts_z = 52;
  ExpectRejected(sample::EarthMovePdu(), RejectReason::kOffTerrain,
                 "posts (40, 50) .. (42, 52) leave the 52 x 52 grid", small);
  small.terrain_posts_x = small.terrain_posts_z = 53;
  EXPECT_FALSE(Validate(sample::EarthMovePdu(), small).has_value());
  // On a rectangular grid each axis has its own bound: columns 40 .. 42 need 43 posts along x,
  // rows 50 .. 52 need 53 along z.
  small.terrain_posts_x = 43;
  EXPECT_FALSE(Validate(sample::EarthMovePdu(), small).has_value());
  small.terrain_posts_x = 42;
  ExpectRejected(sample::EarthMovePdu(), RejectReason::kOffTerrain,
                 "posts (40, 50) .. (42, 52) leave the 42 x 53 grid", small);
  small.terrain_posts_x = 53;
  small.terrain_posts_z = 52;
  ExpectRejected(sample::EarthMovePdu(), RejectReason::kOffTerrain,
                 "posts (40, 50) .. (42, 52) leave the 53 x 52 grid", small);
  // Earth moves travel only as EarthMove PDUs.
  auto c = sample::Construct();
  c.feature_type = static_cast<int16_t>(FeatureType::kEarthMove);
  const auto r = Validate(c, sample::Context());
  ASSERT_TRUE(r.has_value());
  EXPECT_NE(r->detail.find("travels only in EarthMove PDUs"), std::string::npos) << r->detail;
}

TEST(EarthMovePduTest, TheLargestEarthMoveFitsADatagramWithItsTrailer) {
  // kMaxEarthMovePosts posts spread over a full kMaxEarthMoveSpanPosts square.
  std::vector<PostDelta> deltas;
  for (int k = 0; k < kMaxEarthMovePosts; ++k) {
    const int cell = k * (kMaxEarthMoveSpanPosts * kMaxEarthMoveSpanPosts) / kMaxEarthMovePosts;
    deltas.push_back({static_cast<uint16_t>(4000 + cell % kMaxEarthMoveSpanPosts),
                      static_cast<uint16_t>(4000 + cell / kMaxEarthMoveSpanPosts),
                      -kMaxPostDeltaMm});
  }
  deltas.back() = {static_cast<uint16_t>(4000 + kMaxEarthMoveSpanPosts - 1),
                   static_cast<uint16_t>(4000 + kMaxEarthMoveSpanPosts - 1), kMaxPostDeltaMm};
  FeaturePdu f{
      {1, 2, 3}, FeatureParams::EarthMove(deltas), {{1, 2}, static_cast<uint32_t>(kMaxSerial), 1}};
  f.id.number = static_cast<uint32_t>(kMaxSerial);
  ASSERT_TRUE(ValidateFeatureParams(f.params).ok())
      << ValidateFeatureParams(f.params).error().message;
  auto pdu = ToEarthMove(f);
  sample::StampHeader(pdu, kMaxSerial);
  EXPECT_EQ(pdu.columns, kMaxEarthMoveSpanPosts);
  EXPECT_EQ(pdu.rows, kMaxEarthMoveSpanPosts);
  EXPECT_EQ(EncodePdu(pdu).size(), 1168u);  // docs/pdu.md "EarthMove"
  EXPECT_LE(EncodePdu(pdu).size() + kAuthTrailerBytes, kMaxPduBytes);
  EXPECT_FALSE(Validate(pdu, sample::Context()).has_value());
}

}  // namespace
}  // namespace dt
