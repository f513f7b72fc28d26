#include "render/montage.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/bitmap_font.h"

namespace dt {
namespace {

TEST(Montage, PlacesEveryImageWholeInItsTile) {
  const std::vector<Image> images = {Image(20, 10, {255, 0, 0, 255}),
                                     Image(12, 16, {0, 255, 0, 255}),
                                     Image(20, 16, {0, 0, 255, 255})};
  const std::vector<std::string> labels = {"A", "B", "C"};
  MontageOptions o;
  o.separator_px = 3;
  o.label_scale = 1;
  const Image m = Montage(images, labels, o);
  const int label_h = TextHeightPx(1) + 2;
  EXPECT_EQ(m.width(), 3 * (20 + 3) + 3);
  EXPECT_EQ(m.height(), 16 + label_h + 2 * 3);
  for (size_t k = 0; k < images.size(); ++k) {
    const int left = 3 + static_cast<int>(k) * (20 + 3), top = 3 + label_h;
    for (int r = 0; r < images[k].height(); ++r) {
      for (int c = 0; c < images[k].width(); ++c) {
        ASSERT_EQ(m.at(left + c, top + r), images[k].at(c, r)) << k << " " << c << "," << r;
      }
    }
  }
}

TEST(Montage, WrapsIntoRowsAndDrawsLabels) {
  const std::vector<Image> images(3, Image(10, 10, {0, 0, 0, 255}));
  MontageOptions o;
  o.columns = 2;
  o.label_scale = 1;
  const Image labelled = Montage(images, std::vector<std::string>{"N1", "N2", "N3"}, o);
  const Image blank = Montage(images, std::vector<std::string>{"", "", ""}, o);
  EXPECT_EQ(labelled.width(), 2 * (10 + 4) + 4);
  EXPECT_EQ(labelled.height(), 2 * (10 + TextHeightPx(1) + 2 + 4) + 4);
  EXPECT_NE(labelled, blank);
}

TEST(Montage, RefusesMisuse) {
  const std::vector<Image> one(1, Image(4, 4));
  EXPECT_THROW(Montage(std::vector<Image>{}, std::vector<std::string>{}), std::invalid_argument);
  EXPECT_THROW(Montage(one, std::vector<std::string>{"a", "b"}), std::invalid_argument);
  MontageOptions bad;
  bad.label_scale = 0;
  EXPECT_THROW(Montage(one, std::vector<std::string>{"a"}, bad), std::invalid_argument);
  EXPECT_THROW(Montage(std::vector<Image>(1), std::vector<std::string>{"a"}),
               std::invalid_argument);
}

}  // namespace
}  // namespace dt
