#include "terrain/height_grid.h"

#include <algorithm>
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
    HeightGrid g(kMaxGridPostsPerSide + 1, 10.0);
    ADD_FAILURE() << "a grid beyond the maximum was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "posts_per_side = " + std::to_string(kMaxGridPostsPerSide + 1) + " must be in [2, " +
                  std::to_string(kMaxGridPostsPerSide) + "]");
  }
  EXPECT_THROW(HeightGrid(9, kMaxGridPostsPerSide + 1, 1.0), std::invalid_argument);
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

// ---- Rectangular grids: every index and bound along x and along z apart ----

// nx x nz posts at 10 m whose post (i, j) is 100 * j + i, so every post names its own indices.
HeightGrid Labelled(int nx, int nz) {
  std::vector<float> posts;
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) posts.push_back(static_cast<float>(100 * j + i));
  }
  return HeightGrid(nx, nz, 10.0, std::move(posts));
}

TEST(HeightGridRectangle, ShapeAndSizesFollowEachAxis) {
  for (const auto& [nx, nz] : {std::pair{7, 4}, std::pair{4, 7}, std::pair{2, 9}}) {
    const HeightGrid g = Labelled(nx, nz);
    EXPECT_EQ(g.posts_x(), nx);
    EXPECT_EQ(g.posts_z(), nz);
    EXPECT_EQ(g.squares_x(), nx - 1);
    EXPECT_EQ(g.squares_z(), nz - 1);
    EXPECT_DOUBLE_EQ(g.size_x_m(), 10.0 * (nx - 1));
    EXPECT_DOUBLE_EQ(g.size_z_m(), 10.0 * (nz - 1));
    EXPECT_FALSE(g.is_square());
    EXPECT_EQ(g.posts().size(), static_cast<size_t>(nx) * nz);
    EXPECT_EQ(g.soils().size(), static_cast<size_t>(nx - 1) * (nz - 1) * 2);
  }
  EXPECT_TRUE(HeightGrid(5, 5, 1.0).is_square());
  // The square convenience is the rectangle with equal sides.
  EXPECT_TRUE(
      std::ranges::equal(HeightGrid(5, 2.0, 3.0f).posts(), HeightGrid(5, 5, 2.0, 3.0f).posts()));
}

TEST(HeightGridRectangle, PostsAreRowMajorAlongX) {
  for (const auto& [nx, nz] : {std::pair{7, 4}, std::pair{4, 7}}) {
    const HeightGrid g = Labelled(nx, nz);
    for (int j = 0; j < nz; ++j) {
      for (int i = 0; i < nx; ++i) {
        ASSERT_EQ(g.post(i, j), static_cast<float>(100 * j + i)) << i << "," << j;
        ASSERT_EQ(g.posts()[static_cast<size_t>(j) * nx + i], g.post(i, j));
        // Each post stands at (i * spacing, j * spacing).
        ASSERT_DOUBLE_EQ(g.ElevationAt(i * 10.0, j * 10.0), 100.0 * j + i) << i << "," << j;
      }
    }
  }
}

TEST(HeightGridRectangle, ContainsTheRectangleAndNothingBeyondEitherSide) {
  const HeightGrid wide = Labelled(7, 4);  // 60 m x 30 m
  const HeightGrid tall = Labelled(4, 7);  // 30 m x 60 m
  for (auto [x, z] : {std::pair{0.0, 0.0}, std::pair{60.0, 0.0}, std::pair{0.0, 30.0},
                      std::pair{60.0, 30.0}, std::pair{33.3, 29.99}}) {
    EXPECT_TRUE(wide.Contains(x, z)) << x << "," << z;
    EXPECT_TRUE(tall.Contains(z, x)) << z << "," << x;
  }
  for (auto [x, z] : {std::pair{60.001, 0.0}, std::pair{0.0, 30.001}, std::pair{30.0, 40.0},
                      std::pair{-0.001, 10.0}, std::pair{10.0, -0.001}}) {
    EXPECT_FALSE(wide.Contains(x, z)) << x << "," << z;
    EXPECT_FALSE(tall.Contains(z, x)) << z << "," << x;
    EXPECT_THROW(wide.ElevationAt(x, z), std::out_of_range);
    EXPECT_THROW(wide.NormalAt(x, z), std::out_of_range);
    EXPECT_THROW(wide.Locate(x, z), std::out_of_range);
    EXPECT_THROW(wide.SquareAt(x, z), std::out_of_range);
  }
  // A point inside a square grid of the longer side but outside the rectangle.
  EXPECT_FALSE(wide.Contains(50.0, 50.0));
  EXPECT_FALSE(tall.Contains(50.0, 50.0));
}

TEST(HeightGridRectangle, CornersAndFarEdgesBelongToTheLastSquares) {
  const HeightGrid wide = Labelled(7, 4);  // squares 0..5 along x, 0..2 along z
  EXPECT_EQ(wide.SquareAt(0.0, 0.0), (SquareIndex{0, 0}));
  EXPECT_EQ(wide.SquareAt(60.0, 0.0), (SquareIndex{5, 0}));
  EXPECT_EQ(wide.SquareAt(0.0, 30.0), (SquareIndex{0, 2}));
  EXPECT_EQ(wide.SquareAt(60.0, 30.0), (SquareIndex{5, 2}));
  EXPECT_EQ(wide.SquareAt(59.0, 21.0), (SquareIndex{5, 2}));
  EXPECT_EQ(wide.SquareAt(29.0, 29.0), (SquareIndex{2, 2}));
  const HeightGrid tall = Labelled(4, 7);  // squares 0..2 along x, 0..5 along z
  EXPECT_EQ(tall.SquareAt(30.0, 60.0), (SquareIndex{2, 5}));
  EXPECT_EQ(tall.SquareAt(30.0, 0.0), (SquareIndex{2, 0}));
  EXPECT_EQ(tall.SquareAt(0.0, 60.0), (SquareIndex{0, 5}));
  EXPECT_EQ(tall.SquareAt(21.0, 59.0), (SquareIndex{2, 5}));

  // At each corner the elevation is the corner post's, and a point at the far corner lies in the
  // last square's upper triangle with u = v = 1.
  for (const HeightGrid* g : {&wide, &tall}) {
    const int nx = g->posts_x(), nz = g->posts_z();
    const double sx = g->size_x_m(), sz = g->size_z_m();
    EXPECT_DOUBLE_EQ(g->ElevationAt(0.0, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(g->ElevationAt(sx, 0.0), nx - 1);
    EXPECT_DOUBLE_EQ(g->ElevationAt(0.0, sz), 100.0 * (nz - 1));
    EXPECT_DOUBLE_EQ(g->ElevationAt(sx, sz), 100.0 * (nz - 1) + nx - 1);
    const HeightGrid::Location far = g->Locate(sx, sz);
    EXPECT_EQ(far.square, (SquareIndex{nx - 2, nz - 2}));
    EXPECT_DOUBLE_EQ(far.u, 1.0);
    EXPECT_DOUBLE_EQ(far.v, 1.0);
    EXPECT_EQ(g->HalfAt(sx, sz), TriangleHalf::kUpper);
    EXPECT_EQ(g->HalfAt(0.0, 0.0), TriangleHalf::kLower);
    // Along the far edges the elevation interpolates the edge posts only.
    EXPECT_DOUBLE_EQ(g->ElevationAt(sx, 15.0), 150.0 + nx - 1);
    EXPECT_DOUBLE_EQ(g->ElevationAt(15.0, sz), 100.0 * (nz - 1) + 1.5);
    const HeightGrid::Location edge = g->Locate(sx, 15.0);
    EXPECT_EQ(edge.square, (SquareIndex{nx - 2, 1}));
    EXPECT_DOUBLE_EQ(edge.u, 1.0);
    EXPECT_DOUBLE_EQ(edge.v, 0.5);
  }
}

TEST(HeightGridRectangle, NormalsUseTheRightNeighbours) {
  // Rising 1 m per metre along x on a 7 x 4 grid, 2 m per metre along z on a 4 x 7 one: a mixed
  // up index would tilt the normal the wrong way or by the wrong amount.
  std::vector<float> along_x, along_z;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 7; ++i) along_x.push_back(static_cast<float>(10 * i));
  }
  for (int j = 0; j < 7; ++j) {
    for (int i = 0; i < 4; ++i) along_z.push_back(static_cast<float>(20 * j));
  }
  const HeightGrid wide(7, 4, 10.0, std::move(along_x));
  const HeightGrid tall(4, 7, 10.0, std::move(along_z));
  for (auto [x, z] :
       {std::pair{3.0, 3.0}, std::pair{59.0, 29.0}, std::pair{60.0, 30.0}, std::pair{0.0, 30.0}}) {
    const Eigen::Vector3d n = wide.NormalAt(x, z);
    EXPECT_NEAR(n.x(), -std::sqrt(0.5), 1e-12) << x << "," << z;
    EXPECT_NEAR(n.z(), 0.0, 1e-12) << x << "," << z;
    const Eigen::Vector3d m = tall.NormalAt(z, x);
    EXPECT_NEAR(m.x(), 0.0, 1e-12) << z << "," << x;
    EXPECT_NEAR(m.z(), -2.0 / std::sqrt(5.0), 1e-12) << z << "," << x;
  }
}

TEST(HeightGridRectangle, SoilsAreRowMajorBySquareAlongX) {
  HeightGrid g = Labelled(7, 4);
  g.set_soil({5, 2}, TriangleHalf::kUpper, Material::kSand);  // the far corner square
  g.set_soil({5, 0}, TriangleHalf::kLower, Material::kRock);
  g.set_soil({0, 2}, TriangleHalf::kLower, Material::kMud);
  const auto& soils = g.soils();
  EXPECT_EQ(soils[(2 * 6 + 5) * 2 + 1], Material::kSand);
  EXPECT_EQ(soils[(0 * 6 + 5) * 2 + 0], Material::kRock);
  EXPECT_EQ(soils[(2 * 6 + 0) * 2 + 0], Material::kMud);
  EXPECT_EQ(g.soil({5, 2}, TriangleHalf::kUpper), Material::kSand);
  EXPECT_EQ(std::count(soils.begin(), soils.end(), Material::kGrass), 36 - 3);
  // Squares beyond either side are refused, though each index alone fits the other axis.
  EXPECT_THROW(g.set_soil({6, 0}, TriangleHalf::kLower, Material::kSand), std::out_of_range);
  EXPECT_THROW(g.set_soil({0, 3}, TriangleHalf::kLower, Material::kSand), std::out_of_range);
  EXPECT_THROW(g.set_post(7, 0, 1.0f), std::out_of_range);
  EXPECT_THROW(g.set_post(0, 4, 1.0f), std::out_of_range);
  g.set_post(6, 3, -5.0f);
  EXPECT_EQ(g.posts().back(), -5.0f);
}

TEST(HeightGridRectangle, BadShapesNameTheSide) {
  auto message = [](auto make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(message([] { HeightGrid(1, 5, 1.0); }), "posts_x = 1 must be in [2, 16385]");
  EXPECT_EQ(message([] { HeightGrid(5, 16386, 1.0); }), "posts_z = 16386 must be in [2, 16385]");
  EXPECT_EQ(message([] { HeightGrid(7, 4, 1.0, std::vector<float>(4 * 4)); }),
            "16 posts given for a 7 x 4 grid (expected 28)");
  EXPECT_THROW(HeightGrid(7, 4, 0.0), std::invalid_argument);
  // The largest side along one axis only is within the bound.
  EXPECT_EQ(HeightGrid(kMaxPostsPerSide, 2, 1.0).size_x_m(), kMaxPostsPerSide - 1.0);
}

}  // namespace
}  // namespace dt
