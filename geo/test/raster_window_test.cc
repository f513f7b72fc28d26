// RasterWindow: bilinear and cubic interpolation, and nodata in the support.
#include "geo/raster_window.h"

#include <cmath>

#include <gtest/gtest.h>

namespace dt {
namespace {

RasterWindow Plane(int cols, int rows) {
  RasterWindow w;
  w.cols = cols;
  w.rows = rows;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) w.values.push_back(static_cast<float>(2.0 * c - 3.0 * r + 1.0));
  }
  return w;
}

TEST(RasterWindowTest, BothMethodsReproduceAPlaneInside) {
  const RasterWindow w = Plane(8, 6);
  for (Resampling m : {Resampling::kBilinear, Resampling::kCubic}) {
    for (double c : {1.0, 2.25, 3.5, 4.9}) {
      for (double r : {1.0, 1.75, 3.1}) {
        ASSERT_TRUE(w.Sample(c, r, m).has_value());
        EXPECT_NEAR(*w.Sample(c, r, m), 2.0 * c - 3.0 * r + 1.0, 1e-5) << ResamplingName(m);
      }
    }
  }
}

TEST(RasterWindowTest, AtPixelCentresBothGiveThePixel) {
  RasterWindow w = Plane(5, 5);
  w.values[12] = 40.0f;  // a spike at (2, 2)
  EXPECT_DOUBLE_EQ(*w.Sample(2.0, 2.0, Resampling::kBilinear), 40.0);
  EXPECT_NEAR(*w.Sample(2.0, 2.0, Resampling::kCubic), 40.0, 1e-9);
}

TEST(RasterWindowTest, NodataInTheSupportIsNoValue) {
  RasterWindow w = Plane(6, 6);
  w.has_nodata = true;
  w.nodata = -9999.0f;
  w.values[2 * 6 + 3] = -9999.0f;  // (3, 2)
  EXPECT_FALSE(w.Sample(2.5, 1.5, Resampling::kBilinear).has_value());
  EXPECT_TRUE(w.Sample(1.5, 1.5, Resampling::kBilinear).has_value());
  // Cubic reads two pixels each side: (1.5, 1.5) reaches column 3, row 2.
  EXPECT_FALSE(w.Sample(1.5, 1.5, Resampling::kCubic).has_value());
  w.values[0] = std::nanf("");
  EXPECT_FALSE(w.Sample(0.5, 0.5, Resampling::kBilinear).has_value());
}

}  // namespace
}  // namespace dt
