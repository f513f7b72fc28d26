#include "render/image.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "render/bitmap_font.h"
#include "render/image_diff.h"

namespace dt {
namespace {

TEST(Image, RefusesBadSizes) {
  EXPECT_THROW(Image(0, 5), std::invalid_argument);
  EXPECT_THROW(Image(5, -1), std::invalid_argument);
  EXPECT_THROW(Image(Image::kMaxSidePx + 1, 1), std::invalid_argument);
}

TEST(Image, FillRectClipsToTheImage) {
  Image im(4, 3, {0, 0, 0, 255});
  im.FillRect(-2, 1, 2, 10, {9, 8, 7, 255});
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      const bool inside = c < 2 && r >= 1;
      EXPECT_EQ(im.at(c, r), (inside ? Rgba{9, 8, 7, 255} : Rgba{0, 0, 0, 255})) << c << "," << r;
    }
  }
}

TEST(ImageDiff, IdenticalImagesHaveNoDifference) {
  Image a(8, 6, {1, 2, 3, 255});
  const ImageDiff d = DiffImages(a, a);
  EXPECT_EQ(d.differing_pixels, 0u);
  EXPECT_EQ(d.max_channel_delta, 0);
}

TEST(ImageDiff, CountsPixelsAndBoundsThem) {
  Image a(10, 8, {1, 2, 3, 255});
  Image b = a;
  b.set(2, 5, {1, 2, 4, 255});
  b.set(7, 1, {100, 2, 3, 255});
  b.set(4, 3, {1, 2, 3, 0});
  const ImageDiff d = DiffImages(a, b);
  EXPECT_EQ(d.differing_pixels, 3u);
  EXPECT_EQ(d.min_col, 2);
  EXPECT_EQ(d.max_col, 7);
  EXPECT_EQ(d.min_row, 1);
  EXPECT_EQ(d.max_row, 5);
  EXPECT_EQ(d.max_channel_delta, 255);
}

TEST(ImageDiff, RefusesDifferentSizes) {
  EXPECT_THROW(DiffImages(Image(3, 3), Image(3, 4)), std::invalid_argument);
  EXPECT_THROW(DiffPicture(Image(3, 3), Image(4, 3)), std::invalid_argument);
}

TEST(ImageDiff, PictureMarksExactlyTheDifferingPixelsRed) {
  Image a(5, 5, {0, 200, 0, 255});
  Image b = a;
  b.set(3, 1, {0, 201, 0, 255});
  const Image pic = DiffPicture(a, b);
  const Rgba red{255, 0, 0, 255};
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 5; ++c) EXPECT_EQ(pic.at(c, r) == red, c == 3 && r == 1);
  }
}

TEST(BitmapFont, DrawsInsideItsReportedBox) {
  Image im(60, 20, {0, 0, 0, 255});
  const int scale = 2;
  DrawText(im, 1, 2, "A1", {255, 255, 255, 255}, scale);
  const int w = TextWidthPx("A1", scale), h = TextHeightPx(scale);
  int lit = 0;
  for (int r = 0; r < im.height(); ++r) {
    for (int c = 0; c < im.width(); ++c) {
      if (im.at(c, r)[0] == 0) continue;
      ++lit;
      EXPECT_GE(c, 1);
      EXPECT_LT(c, 1 + w);
      EXPECT_GE(r, 2);
      EXPECT_LT(r, 2 + h);
    }
  }
  EXPECT_GT(lit, 0);
}

TEST(BitmapFont, DistinctCharactersDrawDistinctPictures) {
  Image a(10, 10), b(10, 10), c(10, 10);
  DrawText(a, 0, 0, "1", {255, 255, 255, 255}, 1);
  DrawText(b, 0, 0, "7", {255, 255, 255, 255}, 1);
  DrawText(c, 0, 0, "7", {255, 255, 255, 255}, 1);
  EXPECT_GT(DiffImages(a, b).differing_pixels, 0u);
  EXPECT_EQ(DiffImages(b, c).differing_pixels, 0u);
  EXPECT_THROW(DrawText(a, 0, 0, "x", {0, 0, 0, 255}, 0), std::invalid_argument);
}

TEST(BitmapFont, UnitLettersHaveLowerCaseOthersFallBackToUpperCase) {
  auto draw = [](const char* text) {
    Image im(8, 8);
    DrawText(im, 0, 0, text, {255, 255, 255, 255}, 1);
    return im;
  };
  EXPECT_NE(draw("m"), draw("M"));
  EXPECT_NE(draw("k"), draw("K"));
  EXPECT_EQ(draw("x"), draw("X"));
  EXPECT_EQ(draw("~"), draw("?"));
}

}  // namespace
}  // namespace dt
