#include "terrain/feature_params.h"

#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
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

// The message of a refused parameter set, or "" if it is valid.
std::string RefusalOf(const FeatureParams& p) {
  const Status s = ValidateFeatureParams(p);
  return s ? std::string() : s.error().message;
}

TEST(FeatureParams, SizesBelowTheMinimumAreRefused) {
  const double denormal = std::numeric_limits<double>::denorm_min();
  const double below = std::nextafter(kMinFeatureSizeM, 0.0);
  EXPECT_EQ(RefusalOf(FeatureParams::Crater(1, 1, denormal)),
            fmt::format("crater radius_m = {} is outside [0.01, 200]", denormal));
  EXPECT_EQ(RefusalOf(FeatureParams::Crater(1, 1, kMinFeatureSizeM)), "");
  EXPECT_EQ(RefusalOf(FeatureParams::Crater(1, 1, below)),
            fmt::format("crater radius_m = {} is outside [0.01, 200]", below));
  EXPECT_NE(RefusalOf(FeatureParams::Berm(1, 1, 0, below, 4, 2)).find("berm length_m"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Berm(1, 1, 0, 10, below, 2)).find("berm width_m"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Berm(1, 1, 0, 10, 4, denormal)).find("berm height_m"),
            std::string::npos);
  EXPECT_EQ(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, 10, 20, 10, 5, 5)), "");
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, below, 10, 20, 10, 5, 5)).find("width_m"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, below, 20, 10, 5, 5)).find("ramp 1"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, 10, below, 10, 5, 5)).find("span"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, 10, 20, below, 5, 5)).find("ramp 2"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, 10, 20, 10, below, 5)).find("height_m[0]"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, 0, 8, 10, 20, 10, 5, below)).find("height_m[1]"),
            std::string::npos);
}

TEST(FeatureParams, DirectionsAreBoundedToOneTurnEitherWay) {
  EXPECT_EQ(RefusalOf(FeatureParams::Berm(1, 1, 1e300, 10, 4, 2)),
            "berm direction_rad = 1e+300 is outside [-2 pi, 2 pi] (one turn either way)");
  for (double d : {kMaxDirectionRad, -kMaxDirectionRad, 0.0, 4.0, -3.5}) {
    EXPECT_EQ(RefusalOf(FeatureParams::Berm(1, 1, d, 10, 4, 2)), "") << d;
    EXPECT_EQ(RefusalOf(FeatureParams::Bridge(1, 1, d, 8, 10, 20, 10, 5, 5)), "") << d;
  }
  EXPECT_NE(RefusalOf(FeatureParams::Bridge(1, 1, std::nextafter(kMaxDirectionRad, 7.0), 8, 10, 20,
                                            10, 5, 5))
                .find("bridge direction_rad"),
            std::string::npos);
  EXPECT_NE(RefusalOf(FeatureParams::Berm(1, 1, -7, 10, 4, 2)).find("berm direction_rad = -7"),
            std::string::npos);
}

TEST(FeatureParams, CoordinatesAreBounded) {
  EXPECT_EQ(RefusalOf(FeatureParams::Crater(1e300, 1, 5)),
            fmt::format("x_m = 1e+300 is outside [{}, {}]", -kMaxFeatureCoordinateM,
                        kMaxFeatureCoordinateM));
  EXPECT_NE(RefusalOf(FeatureParams::Berm(1, -2e8, 0, 10, 4, 2)).find("z_m = -2"),
            std::string::npos);
  EXPECT_EQ(RefusalOf(FeatureParams::Crater(kMaxFeatureCoordinateM, -kMaxFeatureCoordinateM, 5)),
            "");
}

}  // namespace
}  // namespace dt
