#include "render/scale_bar.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "render/image_diff.h"

namespace dt {
namespace {

TEST(ScaleBar, PicksTheRoundLengthBelowTheLimit) {
  EXPECT_DOUBLE_EQ(RoundScaleLengthM(1999.0), 1000.0);
  EXPECT_DOUBLE_EQ(RoundScaleLengthM(2000.0), 2000.0);
  EXPECT_DOUBLE_EQ(RoundScaleLengthM(4999.0), 2000.0);
  EXPECT_DOUBLE_EQ(RoundScaleLengthM(51.2), 50.0);
  EXPECT_DOUBLE_EQ(RoundScaleLengthM(0.7), 0.5);
  EXPECT_THROW(RoundScaleLengthM(0.0), std::invalid_argument);
  EXPECT_THROW(RoundScaleLengthM(NAN), std::invalid_argument);
}

TEST(ScaleBar, LabelsInMetresOrKilometres) {
  EXPECT_EQ(ScaleLabel(500.0), "500 m");
  EXPECT_EQ(ScaleLabel(2000.0), "2 km");
  EXPECT_EQ(ScaleLabel(0.5), "0.5 m");
}

TEST(ScaleBar, BarLengthMatchesTheScale) {
  // 512 px at 0.5 m per pixel: at most 51.2 m, so a 50 m bar of 100 px.
  Image im(512, 256, {0, 128, 0, 255});
  DrawScaleBar(im, 0.5);
  // The bar is the longest run of black pixels in one row.
  int longest = 0;
  for (int r = 0; r < im.height(); ++r) {
    int run = 0;
    for (int c = 0; c < im.width(); ++c) {
      run = im.at(c, r) == Rgba{0, 0, 0, 255} ? run + 1 : 0;
      longest = std::max(longest, run);
    }
  }
  EXPECT_EQ(longest, 100);
  EXPECT_THROW(DrawScaleBar(im, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace dt
