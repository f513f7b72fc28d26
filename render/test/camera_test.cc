#include "render/camera.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace dt {
namespace {

TEST(Camera, MapPutsNorthUpAndEastRight) {
  const Camera c = Camera::MapOf({0.0, 0.0, 100.0, 50.0}, 200);
  EXPECT_EQ(c.width_px(), 200);
  EXPECT_EQ(c.height_px(), 100);
  EXPECT_DOUBLE_EQ(c.metres_per_pixel(), 0.5);
  EXPECT_DOUBLE_EQ(c.pixel_footprint_m(), 0.5);
  // South-west corner at the bottom-left, north-east at the top-right, whatever the elevation.
  for (double y : {-100.0, 0.0, 1500.0}) {
    const auto sw = c.WorldToPixel({0.0, y, 0.0});
    const auto ne = c.WorldToPixel({100.0, y, 50.0});
    ASSERT_TRUE(sw && ne);
    EXPECT_NEAR(sw->x(), 0.0, 1e-9);
    EXPECT_NEAR(sw->y(), 100.0, 1e-9);
    EXPECT_NEAR(ne->x(), 200.0, 1e-9);
    EXPECT_NEAR(ne->y(), 0.0, 1e-9);
  }
  const auto p = c.WorldToPixel({30.25, 0.0, 10.0});
  EXPECT_NEAR(p->x(), 60.5, 1e-9);
  EXPECT_NEAR(p->y(), 80.0, 1e-9);
  const Rect a = c.map_area();
  EXPECT_DOUBLE_EQ(a.max_x, 100.0);
  EXPECT_DOUBLE_EQ(a.max_z, 50.0);
}

TEST(Camera, PerspectiveCentresTheTargetAndKeepsEastRightOfNorth) {
  // Looking north from the south, raised: east must appear to the right of the target.
  const Camera c =
      Camera::Perspective({50.0, 30.0, -100.0}, {50.0, 0.0, 50.0}, std::numbers::pi / 3, 320, 240);
  const auto t = c.WorldToPixel({50.0, 0.0, 50.0});
  ASSERT_TRUE(t);
  EXPECT_NEAR(t->x(), 160.0, 1e-6);
  EXPECT_NEAR(t->y(), 120.0, 1e-6);
  const auto east = c.WorldToPixel({60.0, 0.0, 50.0});
  EXPECT_GT(east->x(), t->x());
  const auto above = c.WorldToPixel({50.0, 10.0, 50.0});
  EXPECT_LT(above->y(), t->y());
  EXPECT_FALSE(c.WorldToPixel({50.0, 30.0, -200.0}));  // behind the eye
  // A horizontal metre at the target's distance, facing the eye, spans pixel_footprint_m.
  const Eigen::Vector3d to_target = Eigen::Vector3d(0.0, -30.0, 150.0).normalized();
  const Eigen::Vector3d across(1.0, 0.0, 0.0);  // perpendicular to the line of sight
  ASSERT_NEAR(to_target.dot(across), 0.0, 1e-12);
  const auto right =
      c.WorldToPixel(Eigen::Vector3d(50.0, 0.0, 50.0) + c.pixel_footprint_m() * across);
  EXPECT_NEAR(right->x() - t->x(), 1.0, 1e-6);
}

TEST(Camera, PerspectiveStraightDownKeepsNorthUp) {
  const Camera c = Camera::Perspective({0.0, 100.0, 0.0}, {0.0, 0.0, 0.0}, 1.0, 100, 100);
  const auto north = c.WorldToPixel({0.0, 0.0, 10.0});
  const auto east = c.WorldToPixel({10.0, 0.0, 0.0});
  EXPECT_LT(north->y(), 50.0);
  EXPECT_GT(east->x(), 50.0);
}

// The longer side gets the pixels: a wide area as MapOf does, a tall one as high as asked.
TEST(Camera, MapFittingGivesTheLongerSideThePixels) {
  const Camera square = Camera::MapFitting({0.0, 0.0, 640.0, 640.0}, 512);
  EXPECT_EQ(square.width_px(), 512);
  EXPECT_EQ(square.height_px(), 512);
  EXPECT_EQ(square.metres_per_pixel(),
            Camera::MapOf({0.0, 0.0, 640.0, 640.0}, 512).metres_per_pixel());
  const Camera wide = Camera::MapFitting({0.0, 0.0, 640.0, 160.0}, 512);
  EXPECT_EQ(wide.width_px(), 512);
  EXPECT_EQ(wide.height_px(), 128);
  const Camera tall = Camera::MapFitting({0.0, 0.0, 160.0, 640.0}, 512);
  EXPECT_EQ(tall.width_px(), 128);
  EXPECT_EQ(tall.height_px(), 512);
  EXPECT_DOUBLE_EQ(tall.metres_per_pixel(), 1.25);
  const Rect area = tall.map_area();
  EXPECT_DOUBLE_EQ(area.min_x, 0.0);
  EXPECT_DOUBLE_EQ(area.max_x, 160.0);
  EXPECT_DOUBLE_EQ(area.max_z, 640.0);
  // A sliver keeps at least one pixel.
  EXPECT_EQ(Camera::MapFitting({0.0, 0.0, 1.0, 4000.0}, 512).width_px(), 1);
  EXPECT_THROW(Camera::MapFitting({0, 0, 0, 10}, 10), std::invalid_argument);
  EXPECT_THROW(Camera::MapFitting({0, 0, 10, 10}, 0), std::invalid_argument);
}

TEST(Camera, RefusesBadParameters) {
  EXPECT_THROW(Camera::Map(0, 0, 0.0, 10, 10), std::invalid_argument);
  EXPECT_THROW(Camera::Map(0, 0, 1.0, 0, 10), std::invalid_argument);
  EXPECT_THROW(Camera::Map(NAN, 0, 1.0, 10, 10), std::invalid_argument);
  EXPECT_THROW(Camera::MapOf({0, 0, 0, 10}, 10), std::invalid_argument);
  EXPECT_THROW(Camera::Perspective({1, 1, 1}, {1, 1, 1}, 1.0, 10, 10), std::invalid_argument);
  EXPECT_THROW(Camera::Perspective({0, 1, 0}, {1, 1, 1}, 4.0, 10, 10), std::invalid_argument);
  EXPECT_THROW(Camera::Perspective({0, 1, 0}, {1, 1, 1}, 1.0, 10, 10, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace dt
