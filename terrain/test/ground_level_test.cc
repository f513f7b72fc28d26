#include "terrain/ground_level.h"

#include <algorithm>
#include <stdexcept>

#include <gtest/gtest.h>

#include "terrain/random_terrain.h"

namespace dt {
namespace {

TEST(CoarseGround, ASmallGroundIsItself) {
  const HeightGrid g = MakeRandomTerrain({.posts_x = 65, .posts_z = 33, .spacing_m = 2.0});
  EXPECT_EQ(CoarseStride(g, 65), 1);
  const HeightGrid c = CoarseGround(g, 65);
  EXPECT_EQ(c.posts_x(), 65);
  EXPECT_TRUE(std::ranges::equal(c.posts(), g.posts()));
}

TEST(CoarseGround, ALargeGroundKeepsEveryStrideThPostOverTheSameExtent) {
  HeightGrid g = MakeRandomTerrain({.posts_x = 401, .posts_z = 201, .spacing_m = 3.0});
  g.set_soil({8, 4}, TriangleHalf::kUpper, Material::kRock);
  // 400 squares into at most 99: stride 5 (4 would leave 100).
  EXPECT_EQ(CoarseStride(g, 100), 5);
  const HeightGrid c = CoarseGround(g, 100);
  EXPECT_EQ(c.posts_x(), 81);
  EXPECT_EQ(c.posts_z(), 41);
  EXPECT_EQ(c.spacing_m(), 15.0);
  EXPECT_EQ(c.size_x_m(), g.size_x_m());
  EXPECT_EQ(c.size_z_m(), g.size_z_m());
  for (int j = 0; j < c.posts_z(); ++j) {
    for (int i = 0; i < c.posts_x(); ++i) ASSERT_EQ(c.post(i, j), g.post(5 * i, 5 * j));
  }
  EXPECT_EQ(c.soil({1, 0}, TriangleHalf::kUpper), Material::kGrass);
  HeightGrid h = g;
  h.set_soil({5, 0}, TriangleHalf::kUpper, Material::kRock);
  EXPECT_EQ(CoarseGround(h, 100).soil({1, 0}, TriangleHalf::kUpper), Material::kRock);
  EXPECT_THROW(CoarseGround(g, 1), std::invalid_argument);
}

TEST(CoarseGround, AnUnevenSideEndsAtTheLastWholeStride) {
  const HeightGrid g = MakeRandomTerrain({.posts_x = 403, .posts_z = 11, .spacing_m = 1.0});
  const HeightGrid c = CoarseGround(g, 100);  // 402 squares: stride 5, 80 coarse squares
  EXPECT_EQ(c.posts_x(), 81);
  EXPECT_EQ(c.posts_z(), 3);
  EXPECT_GT(c.size_x_m(), g.size_x_m() - c.spacing_m());
  EXPECT_LE(c.size_x_m(), g.size_x_m());
}

}  // namespace
}  // namespace dt
