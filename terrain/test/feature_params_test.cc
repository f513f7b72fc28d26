#include "terrain/feature_params.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dt {
namespace {

TEST(FeatureParams, EncodeDecodeIsTheIdentity) {
  FeatureParams p = FeatureParams::Crater(12.5, 40.25, 6.0, Material::kDirt);
  p.vertex_edits = {{0, 1, 0.25}, {3, 2, -0.5}};
  ByteWriter w;
  EncodeFeatureParams(p, w);
  ByteReader r(w.bytes());
  auto back = DecodeFeatureParams(r);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), p);
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(FeatureParams, TruncatedRecordNamesTheByte) {
  ByteWriter w;
  EncodeFeatureParams(FeatureParams::Berm(1, 2, 0.5, 30, 4, 2), w);
  auto bytes = w.bytes();
  bytes.resize(bytes.size() - 3);
  ByteReader r(bytes);
  auto back = DecodeFeatureParams(r);
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.error().message.find("truncated"), std::string::npos);
}

TEST(FeatureParams, ValidationRejectsBadValuesWithTheirNames) {
  EXPECT_TRUE(ValidateFeatureParams(FeatureParams::Crater(1, 1, 5)).ok());
  auto zero = ValidateFeatureParams(FeatureParams::Crater(1, 1, 0));
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.error().message.find("radius_m = 0"), std::string::npos);
  EXPECT_FALSE(ValidateFeatureParams(FeatureParams::Crater(NAN, 1, 5)).ok());
  EXPECT_FALSE(ValidateFeatureParams(FeatureParams::Crater(1, 1, kMaxCraterRadiusM * 2)).ok());
  EXPECT_FALSE(ValidateFeatureParams(FeatureParams::Berm(1, 1, 0, 10, -1, 2)).ok());
  EXPECT_FALSE(ValidateFeatureParams(FeatureParams::Berm(1, 1, INFINITY, 10, 1, 2)).ok());
  EXPECT_FALSE(ValidateFeatureParams(FeatureParams::Bridge(1, 1, 0, 8, 10, 0, 10, 5, 5)).ok());
  FeatureParams bad_type = FeatureParams::Crater(1, 1, 5);
  bad_type.type = static_cast<FeatureType>(9);
  EXPECT_FALSE(ValidateFeatureParams(bad_type).ok());
  FeatureParams bad_material = FeatureParams::Crater(1, 1, 5);
  bad_material.material = static_cast<Material>(99);
  EXPECT_FALSE(ValidateFeatureParams(bad_material).ok());
  FeatureParams unsorted = FeatureParams::Crater(1, 1, 5);
  unsorted.vertex_edits = {{3, 0, 1.0}, {1, 0, 1.0}};
  EXPECT_FALSE(ValidateFeatureParams(unsorted).ok());
  FeatureParams off_mesh = FeatureParams::Crater(1, 1, 5);
  off_mesh.vertex_edits = {{16, 0, 1.0}};
  EXPECT_FALSE(ValidateFeatureParams(off_mesh).ok());
}

}  // namespace
}  // namespace dt
