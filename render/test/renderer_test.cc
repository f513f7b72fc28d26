#include "render/renderer.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/image_diff.h"
#include "render/png_io.h"
#include "terrain/random_terrain.h"

namespace dt {
namespace {

constexpr double kPi = std::numbers::pi;

// 256 m x 256 m at 4 m spacing, with relief so shading varies.
HeightGrid Ground() {
  RandomTerrainParams p;
  p.posts_x = p.posts_z = 65;
  p.spacing_m = 4.0;
  p.relief_m = 12.0;
  p.seed = 7;
  return MakeRandomTerrain(p);
}

HeightGrid FlatGround() { return HeightGrid(65, 4.0, 10.0f, Material::kGrass); }

struct Placed {
  FeatureId id;
  FeatureParams params;
};

std::vector<Placed> SomeFeatures() {
  return {
      {{1, 1, 1}, FeatureParams::Crater(60.0, 70.0, 15.0)},
      {{1, 1, 2}, FeatureParams::Crater(70.0, 75.0, 8.0, Material::kSand)},  // overlaps the first
      {{1, 2, 1}, FeatureParams::Berm(150.0, 40.0, 0.6, 60.0, 9.0, 3.0)},
      {{2, 1, 1}, FeatureParams::Bridge(120.0, 170.0, 0.2, 10.0, 25.0, 50.0, 25.0, 8.0, 9.0)},
  };
}

Terrain Build(HeightGrid ground, const std::vector<Placed>& features) {
  Terrain t(std::move(ground));
  for (const Placed& p : features) {
    const Status s = t.Add(p.id, p.params);
    EXPECT_TRUE(s.ok()) << p.id.ToString() << ": " << (s.ok() ? "" : s.error().message);
  }
  return t;
}

VehicleSprite SpriteAt(const Terrain& t, double x, double z, double heading) {
  VehicleSprite v;
  v.x_m = x;
  v.z_m = z;
  v.y_m = t.ElevationAt(x, z);
  v.heading_rad = heading;
  return v;
}

Camera MapCamera(const Terrain& t, int width_px = 256) {
  return Camera::MapOf({0.0, 0.0, t.ground().size_x_m(), t.ground().size_z_m()}, width_px);
}

Camera Oblique() {
  return Camera::Perspective({-60.0, 120.0, -60.0}, {128.0, 0.0, 128.0}, kPi / 3, 320, 240);
}

// The pixel a world point falls in, which must be on the image.
std::pair<int, int> PixelOf(const Camera& c, double x, double y, double z) {
  const auto p = c.WorldToPixel({x, y, z});
  EXPECT_TRUE(p.has_value());
  const int col = static_cast<int>(std::floor(p->x())), row = static_cast<int>(std::floor(p->y()));
  EXPECT_TRUE(col >= 0 && row >= 0 && col < c.width_px() && row < c.height_px());
  return {col, row};
}

class RendererTest : public ::testing::Test {
 protected:
  Renderer renderer_;
};

TEST_F(RendererTest, SameStateTwiceGivesTheSamePixels) {
  const Terrain t = Build(Ground(), SomeFeatures());
  const std::vector<VehicleSprite> vehicles = {SpriteAt(t, 100, 100, 0.3),
                                               SpriteAt(t, 200, 60, 2.0)};
  RenderOptions o;
  o.grid_spacing_m = 50.0;
  for (const Camera& c : {MapCamera(t), Oblique()}) {
    const Image a = renderer_.Render(t, vehicles, c, o);
    const Image b = renderer_.Render(t, vehicles, c, o);
    EXPECT_EQ(DiffImages(a, b).differing_pixels, 0u);
    // Something was drawn: the image is not a single colour.
    EXPECT_GT(DiffImages(a, Image(a.width(), a.height(), a.at(0, 0))).differing_pixels, 1000u);
  }
}

TEST_F(RendererTest, AFreshRendererGivesTheSamePixels) {
  const Terrain t = Build(Ground(), SomeFeatures());
  Renderer other;
  const Image a = renderer_.Render(t, {}, Oblique());
  const Image b = other.Render(t, {}, Oblique());
  EXPECT_EQ(DiffImages(a, b).differing_pixels, 0u);
}

TEST_F(RendererTest, InsertionOrderDoesNotChangeThePixels) {
  std::vector<Placed> forward = SomeFeatures();
  std::vector<Placed> backward(forward.rbegin(), forward.rend());
  const Terrain a = Build(Ground(), forward);
  // The second replica also saw a feature come and go.
  Terrain b(Ground());
  ASSERT_TRUE(b.Add({9, 9, 9}, FeatureParams::Crater(200.0, 200.0, 20.0)).ok());
  for (const Placed& p : backward) ASSERT_TRUE(b.Add(p.id, p.params).ok());
  ASSERT_TRUE(b.Remove({9, 9, 9}).ok());
  // And one feature reached its parameters through an update: a bridge destroyed, then repaired.
  FeatureParams broken = forward.back().params;
  broken.status = BridgeStatus::kDestroyed;
  ASSERT_TRUE(b.Update(forward.back().id, broken).ok());
  ASSERT_TRUE(b.Update(forward.back().id, forward.back().params).ok());
  RenderOptions o;
  o.grid_spacing_m = 32.0;
  for (const Camera& c : {MapCamera(a), Oblique()}) {
    const ImageDiff d = DiffImages(renderer_.Render(a, {}, c, o), renderer_.Render(b, {}, c, o));
    EXPECT_EQ(d.differing_pixels, 0u)
        << "box " << d.min_col << "," << d.min_row << " - " << d.max_col << "," << d.max_row;
  }
}

TEST_F(RendererTest, RefinedAndPlainSquaresMeetWithoutPinholes) {
  // Many small earthworks on rough ground: every refined square borders plain ones. Looking over
  // the terrain from low down, the lower half of the picture is all ground; a T-junction would
  // let the background through as isolated pixels.
  RandomTerrainParams p;
  p.posts_x = p.posts_z = 129;
  p.spacing_m = 4.0;
  p.relief_m = 30.0;
  p.seed = 3;
  Terrain t(MakeRandomTerrain(p));
  uint32_t n = 0;
  for (int a = 0; a < 8; ++a) {
    for (int b = 0; b < 8; ++b) {
      const double x = 40.0 + 55.0 * a + 3.3 * b, z = 40.0 + 55.0 * b + 2.1 * a;
      const Status s =
          (a + b) % 3 == 0
              ? t.Add({1, 2, ++n}, FeatureParams::Berm(x, z, 0.4 * a + 0.1 * b, 30.0, 5.0, 2.0))
              : t.Add({1, 1, ++n}, FeatureParams::Crater(x, z, 3.0 + 2.5 * b));
      ASSERT_TRUE(s.ok()) << s.error().message;
    }
  }
  RenderOptions o;
  o.scale_bar = false;
  for (double eye_x : {256.0, 356.0, 456.0}) {
    const Camera c = Camera::Perspective({eye_x, 60.0, 100.0}, {256.0, 0.0, 300.0}, 1.0, 400, 300);
    const Image im = renderer_.Render(t, {}, c, o);
    int holes = 0;
    for (int r = im.height() / 2; r < im.height(); ++r) {
      for (int col = 0; col < im.width(); ++col) holes += im.at(col, r) == o.background;
    }
    EXPECT_EQ(holes, 0) << "eye x " << eye_x;
  }
}

TEST_F(RendererTest, CraterRimDiffersFromBareGroundWhereTheRimIs) {
  const double cx = 128.0, cz = 128.0, r = 30.0;
  const Terrain bare(FlatGround());
  const Terrain cratered = Build(FlatGround(), {{{1, 1, 1}, FeatureParams::Crater(cx, cz, r)}});
  RenderOptions o;
  o.scale_bar = false;
  const double rim_y = cratered.ElevationAt(cx + 0.7 * r, cz);
  ASSERT_GT(rim_y, 10.0);
  // Zoomed in on the crater, only the squares under the map are drawn; the rim still shows.
  const Camera zoom = Camera::MapOf({cx - 1.5 * r, cz - 1.5 * r, cx + 1.5 * r, cz + 1.5 * r}, 300);
  const Image zoom_before = renderer_.Render(bare, {}, zoom, o);
  const Image zoom_after = renderer_.Render(cratered, {}, zoom, o);
  // Bare flat ground fills the whole zoomed map with one colour: no background shows.
  EXPECT_EQ(DiffImages(zoom_before, Image(300, 300, zoom_before.at(0, 0))).differing_pixels, 0u);
  EXPECT_NE(zoom_before.at(0, 0), o.background);
  for (int k = 0; k < 16; ++k) {
    const double a = k * kPi / 8;
    const double x = cx + 0.7 * r * std::cos(a), z = cz + 0.7 * r * std::sin(a);
    const auto [col, row] = PixelOf(zoom, x, rim_y, z);
    EXPECT_NE(zoom_after.at(col, row), zoom_before.at(col, row)) << "spoke " << k;
  }
  const Camera c = MapCamera(bare);
  const Image before = renderer_.Render(bare, {}, c, o);
  const Image after = renderer_.Render(cratered, {}, c, o);
  for (int k = 0; k < 16; ++k) {
    const double a = k * kPi / 8 + kPi / 16;
    const double x = cx + 0.7 * r * std::cos(a), z = cz + 0.7 * r * std::sin(a);
    const auto [col, row] = PixelOf(c, x, cratered.ElevationAt(x, z), z);
    EXPECT_NE(after.at(col, row), before.at(col, row)) << "spoke " << k;
    // Within the same picture the rim stands out from bare ground far from the crater.
    const auto [bc, br] = PixelOf(c, 10.0 + k, 10.0, 240.0);
    EXPECT_NE(after.at(col, row), after.at(bc, br)) << "spoke " << k;
  }
  // Nothing changes well outside the crater.
  const ImageDiff d = DiffImages(before, after);
  const auto [min_c, max_r] = PixelOf(c, cx - r - 2.0, 10.0, cz - r - 2.0);
  const auto [max_c, min_r] = PixelOf(c, cx + r + 2.0, 10.0, cz + r + 2.0);
  EXPECT_GE(d.min_col, min_c);
  EXPECT_LE(d.max_col, max_c);
  EXPECT_GE(d.min_row, min_r);
  EXPECT_LE(d.max_row, max_r);
}

TEST_F(RendererTest, BermShowsAlongItsCrest) {
  const Terrain bare(FlatGround());
  const Terrain bermed = Build(
      FlatGround(), {{{1, 1, 1}, FeatureParams::Berm(60.0, 60.0, kPi / 4, 100.0, 12.0, 4.0)}});
  const Camera c = MapCamera(bare);
  const Image before = renderer_.Render(bare, {}, c);
  const Image after = renderer_.Render(bermed, {}, c);
  for (double along : {10.0, 50.0, 90.0}) {
    const double x = 60.0 + along * std::cos(kPi / 4), z = 60.0 + along * std::sin(kPi / 4);
    const auto [col, row] = PixelOf(c, x, bermed.ElevationAt(x, z), z);
    EXPECT_NE(after.at(col, row), before.at(col, row)) << along;
  }
}

TEST_F(RendererTest, DestroyedBridgeDiffersFromIntactWhereTheSpanIs) {
  FeatureParams bridge =
      FeatureParams::Bridge(80.0, 128.0, 0.0, 12.0, 30.0, 80.0, 30.0, 10.0, 10.0);
  const Terrain intact = Build(FlatGround(), {{{1, 1, 1}, bridge}});
  bridge.status = BridgeStatus::kDestroyed;
  const Terrain destroyed = Build(FlatGround(), {{{1, 1, 1}, bridge}});
  const Terrain bare(FlatGround());
  for (const Camera& c :
       {MapCamera(bare),
        Camera::Perspective({120.0, 40.0, 20.0}, {120.0, 10.0, 128.0}, kPi / 3, 320, 240)}) {
    const Image a = renderer_.Render(intact, {}, c);
    const Image b = renderer_.Render(destroyed, {}, c);
    const Image g = renderer_.Render(bare, {}, c);
    EXPECT_GT(DiffImages(a, b).differing_pixels, 20u);
    EXPECT_GT(DiffImages(a, g).differing_pixels, 100u);  // the bridge is drawn at all
    EXPECT_GT(DiffImages(b, g).differing_pixels, 100u);  // and so is the broken one
  }
  // From the side, the intact span's middle stands 10 m up; the broken one's lies on the ground.
  const Camera side =
      Camera::Perspective({120.0, 12.0, 20.0}, {120.0, 12.0, 128.0}, kPi / 3, 320, 240);
  const auto [col, row] = PixelOf(side, 120.0, 10.0 + 9.5, 128.0);
  const Image a = renderer_.Render(intact, {}, side);
  const Image b = renderer_.Render(destroyed, {}, side);
  const Image g = renderer_.Render(bare, {}, side);
  EXPECT_NE(a.at(col, row), g.at(col, row));  // deck side where the intact span stands
  EXPECT_EQ(b.at(col, row), g.at(col, row));  // sky there once the span has fallen
}

TEST_F(RendererTest, VehicleAppearsAtItsPosition) {
  const Terrain t(FlatGround());
  const Camera c = MapCamera(t);
  RenderOptions o;
  o.scale_bar = false;
  const Image empty = renderer_.Render(t, {}, c, o);
  for (auto [x, z] : {std::pair{60.0, 190.0}, std::pair{200.0, 40.0}}) {
    VehicleSprite v = SpriteAt(t, x, z, 0.7);
    const Image with = renderer_.Render(t, std::vector<VehicleSprite>{v}, c, o);
    const auto [col, row] = PixelOf(c, x, v.y_m + v.height_m, z);
    EXPECT_NE(with.at(col, row), empty.at(col, row));
    // Every changed pixel lies within the vehicle's half-diagonal of its position.
    const ImageDiff d = DiffImages(empty, with);
    const double reach_px = 0.5 * std::hypot(v.length_m, v.width_m) / c.metres_per_pixel() + 1.0;
    EXPECT_GE(d.min_col, col - reach_px);
    EXPECT_LE(d.max_col, col + reach_px);
    EXPECT_GE(d.min_row, row - reach_px);
    EXPECT_LE(d.max_row, row + reach_px);
  }
}

TEST_F(RendererTest, PitchAndRollChangeTheVehicle) {
  const Terrain t(FlatGround());
  const Camera c =
      Camera::Perspective({100.0, 16.0, 110.0}, {120.0, 10.0, 128.0}, kPi / 4, 320, 240);
  VehicleSprite level = SpriteAt(t, 120.0, 128.0, 0.0);
  VehicleSprite pitched = level, rolled = level;
  pitched.pitch_rad = 0.3;
  rolled.roll_rad = 0.3;
  const Image a = renderer_.Render(t, std::vector<VehicleSprite>{level}, c);
  const Image b = renderer_.Render(t, std::vector<VehicleSprite>{pitched}, c);
  const Image r = renderer_.Render(t, std::vector<VehicleSprite>{rolled}, c);
  EXPECT_GT(DiffImages(a, b).differing_pixels, 50u);
  EXPECT_GT(DiffImages(a, r).differing_pixels, 50u);
  EXPECT_GT(DiffImages(b, r).differing_pixels, 50u);
  // Pitch up: the nose's roof corner rises. Roll right: the right roof edge drops.
  const auto nose_level = c.WorldToPixel({123.5, 10.0 + 2.5, 128.0});
  const auto nose_up = c.WorldToPixel({120.0 + 3.5 * std::cos(0.3) - 2.5 * std::sin(0.3),
                                       10.0 + 3.5 * std::sin(0.3) + 2.5 * std::cos(0.3), 128.0});
  EXPECT_LT(nose_up->y(), nose_level->y());
}

TEST_F(RendererTest, GridOverlayDrawsOnItsLines) {
  const Terrain t(FlatGround());
  const Camera c = MapCamera(t);
  RenderOptions plain, grid;
  grid.grid_spacing_m = 64.0;
  const Image a = renderer_.Render(t, {}, c, plain);
  const Image b = renderer_.Render(t, {}, c, grid);
  // The line x = 64 m runs along a pixel boundary: the rasteriser lights the column on one side.
  const auto [col, row] = PixelOf(c, 64.0 + 0.2, 10.0, 100.0);
  EXPECT_TRUE(a.at(col, row) != b.at(col, row) || a.at(col - 1, row) != b.at(col - 1, row));
  const auto [col2, row2] = PixelOf(c, 96.0, 10.0, 100.0);  // between lines
  EXPECT_EQ(a.at(col2, row2), b.at(col2, row2));
}

TEST_F(RendererTest, ScaleBarSitsInTheLowerLeftCorner) {
  const Terrain t(FlatGround());
  const Camera c = MapCamera(t);
  RenderOptions with, without;
  without.scale_bar = false;
  const ImageDiff d =
      DiffImages(renderer_.Render(t, {}, c, with), renderer_.Render(t, {}, c, without));
  EXPECT_GT(d.differing_pixels, 0u);
  EXPECT_LT(d.max_col, c.width_px() / 2);
  EXPECT_GT(d.min_row, c.height_px() / 2);
}

TEST_F(RendererTest, RenderedPngDecodesToTheSamePixels) {
  const Terrain t = Build(Ground(), SomeFeatures());
  const Image im =
      renderer_.Render(t, std::vector<VehicleSprite>{SpriteAt(t, 90, 90, 1.0)}, MapCamera(t));
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("dt_render_test_" + std::to_string(::getpid()) + ".png"))
                               .string();
  ASSERT_TRUE(WritePng(im, path).ok());
  const Result<Image> back = ReadPng(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(DiffImages(im, back.value()).differing_pixels, 0u);
}

TEST_F(RendererTest, RefusesBadOptionsAndVehicles) {
  const Terrain t(FlatGround());
  RenderOptions o;
  o.grid_spacing_m = -1.0;
  EXPECT_THROW(renderer_.Render(t, {}, MapCamera(t), o), std::invalid_argument);
  VehicleSprite v;
  v.length_m = 0.0;
  EXPECT_THROW(renderer_.Render(t, std::vector<VehicleSprite>{v}, MapCamera(t)),
               std::invalid_argument);
  v = VehicleSprite{};
  v.roll_rad = NAN;
  EXPECT_THROW(renderer_.Render(t, std::vector<VehicleSprite>{v}, MapCamera(t)),
               std::invalid_argument);
}

}  // namespace
}  // namespace dt
