#include "terrain/height_grid.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace dt {
namespace {

// A 3 x 3 grid, 10 m spacing, with distinct corner heights so each triangle is identifiable.
HeightGrid SlopedGrid() {
  // index = j * 3 + i
  return HeightGrid(3, 10.0, std::vector<float>{0, 10, 20, 5, 15, 25, 10, 20, 40});
}

TEST(HeightGrid, PostsAreExactAtTheirPositions) {
  const HeightGrid g = SlopedGrid();
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_DOUBLE_EQ(g.ElevationAt(i * 10.0, j * 10.0), g.post(i, j)) << i << "," << j;
    }
  }
}

TEST(HeightGrid, DiagonalRunsTopLeftToBottomRight) {
  // Square (0,0): h00=0, h10=10, h01=5, h11=15. The lower triangle holds (x0,z0).
  HeightGrid g(2, 10.0, std::vector<float>{0, 10, 5, 100});
  EXPECT_EQ(g.HalfAt(2.0, 2.0), TriangleHalf::kLower);
  EXPECT_EQ(g.HalfAt(8.0, 8.0), TriangleHalf::kUpper);
  // The lower triangle ignores the far corner (100 m): at (2, 2) the plane of h00, h10, h01.
  EXPECT_DOUBLE_EQ(g.ElevationAt(2.0, 2.0), 0.0 + 0.2 * 10.0 + 0.2 * 5.0);
  // Along the diagonal both planes agree: midpoint of (0,10)-(10,0) is the mean of h01, h10.
  EXPECT_DOUBLE_EQ(g.ElevationAt(5.0, 5.0), 7.5);
  // The upper triangle uses h11 = 100.
  EXPECT_GT(g.ElevationAt(9.0, 9.0), 80.0);
}

TEST(HeightGrid, NormalPointsUpAndAgainstTheSlope) {
  // Ground rising 1 m per metre toward +x.
  HeightGrid g(2, 10.0, std::vector<float>{0, 10, 0, 10});
  const Eigen::Vector3d n = g.NormalAt(3.0, 3.0);
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(n.x(), -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(n.y(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(n.z(), 0.0, 1e-12);
}

TEST(HeightGrid, FarEdgeBelongsToLastSquare) {
  const HeightGrid g = SlopedGrid();
  EXPECT_EQ(g.SquareAt(20.0, 20.0), (SquareIndex{1, 1}));
  EXPECT_DOUBLE_EQ(g.ElevationAt(20.0, 20.0), 40.0);
}

TEST(HeightGrid, OutOfBoundsAndNanAreRejected) {
  const HeightGrid g = SlopedGrid();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(g.ElevationAt(-0.1, 5.0), std::out_of_range);
  EXPECT_THROW(g.ElevationAt(5.0, 20.01), std::out_of_range);
  EXPECT_THROW(g.ElevationAt(nan, 5.0), std::out_of_range);
  EXPECT_THROW(g.ElevationAt(5.0, inf), std::out_of_range);
  EXPECT_FALSE(g.Contains(nan, nan));
}

TEST(HeightGrid, BadShapesAreRefused) {
  EXPECT_THROW(HeightGrid(1, 10.0), std::invalid_argument);
  EXPECT_THROW(HeightGrid(3, 0.0), std::invalid_argument);
  EXPECT_THROW(HeightGrid(3, -1.0), std::invalid_argument);
  EXPECT_THROW(HeightGrid(3, std::nan("")), std::invalid_argument);
  EXPECT_THROW(HeightGrid(2, 1.0, std::vector<float>{0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(HeightGrid(2, 1.0, std::vector<float>{0, 0, 0, std::nanf("")}),
               std::invalid_argument);
  EXPECT_THROW(HeightGrid(2, 1.0, 0.0f, Material::kFromGround), std::invalid_argument);
}

TEST(HeightGrid, AGridBeyondTheMaximumIsRefusedBeforeAllocating) {
  // (65536 posts a side would need 16 GiB of elevations alone, so it is not tried here.)
  try {
    HeightGrid g(kMaxPostsPerSide + 1, 10.0);
    ADD_FAILURE() << "a grid beyond the maximum was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "posts_per_side = " + std::to_string(kMaxPostsPerSide + 1) +
                                         " must be in [2, " + std::to_string(kMaxPostsPerSide) +
                                         "]");
  }
  EXPECT_EQ(HeightGrid(kMaxPostsPerSide, 10.0).posts().size(),
            static_cast<size_t>(kMaxPostsPerSide) * kMaxPostsPerSide);
}

TEST(HeightGrid, SetPostChangesOnlyNearbyElevations) {
  HeightGrid g(4, 10.0);
  g.set_post(1, 1, 7.0f);
  EXPECT_DOUBLE_EQ(g.ElevationAt(10.0, 10.0), 7.0);
  EXPECT_DOUBLE_EQ(g.ElevationAt(25.0, 25.0), 0.0);
  EXPECT_THROW(g.set_post(4, 0, 1.0f), std::out_of_range);
  EXPECT_THROW(g.set_post(0, 0, std::nanf("")), std::invalid_argument);
}

TEST(HeightGrid, SoilIsPerTriangle) {
  HeightGrid g(3, 10.0);
  g.set_soil({0, 0}, TriangleHalf::kUpper, Material::kSand);
  EXPECT_EQ(g.soil({0, 0}, TriangleHalf::kUpper), Material::kSand);
  EXPECT_EQ(g.soil({0, 0}, TriangleHalf::kLower), Material::kGrass);
  EXPECT_THROW(g.set_soil({2, 0}, TriangleHalf::kLower, Material::kSand), std::out_of_range);
  EXPECT_THROW(g.set_soil({0, 0}, TriangleHalf::kLower, Material::kFromGround),
               std::invalid_argument);
}

}  // namespace
}  // namespace dt
