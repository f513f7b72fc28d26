// RenderMapPng: a process's map render shows every vehicle, however small its pixels are.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "render/png_io.h"
#include "runtime/process_runtime.h"
#include "terrain/terrain.h"

namespace dt {
namespace {

int CountColour(const Image& image, Rgba colour) {
  int n = 0;
  for (int r = 0; r < image.height(); ++r) {
    for (int c = 0; c < image.width(); ++c) {
      const Rgba p = image.at(c, r);
      n += p[0] == colour[0] && p[1] == colour[1] && p[2] == colour[2] ? 1 : 0;
    }
  }
  return n;
}

TEST(RenderMapTest, AVehicleNarrowerThanAPixelStillShows) {
  // 1280 m on 512 pixels: 2.5 m each. A truck 2.4 m wide, heading east, centred on a row
  // boundary (z = 700 m: row 232.0) covers no pixel centre across its width at its true size.
  const Terrain terrain{HeightGrid(129, 10.0, 0.0f)};
  const VehicleSprite truck{.x_m = 600.0,
                            .z_m = 700.0,
                            .length_m = 6.7,
                            .width_m = 2.4,
                            .height_m = 1.4,
                            .colour = {230, 160, 20, 255}};
  const std::string path =
      (std::filesystem::temp_directory_path() / "dt_render_map_test.png").string();
  ASSERT_TRUE(RenderMapPng(terrain, std::vector<VehicleSprite>{truck}, path));
  const Result<Image> image = ReadPng(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(image) << image.error().message;
  ASSERT_EQ(image.value().width(), kMapRenderPx);
  // The roof (flat, so unshaded) in the truck's colour, at its place: column 240, rows 231-232.
  EXPECT_GE(CountColour(image.value(), truck.colour), 2);
  bool at_place = false;
  for (int r = 230; r <= 233; ++r) {
    for (int c = 237; c <= 243; ++c) {
      const Rgba p = image.value().at(c, r);
      at_place |= p[0] == truck.colour[0] && p[1] == truck.colour[1] && p[2] == truck.colour[2];
    }
  }
  EXPECT_TRUE(at_place);
}

}  // namespace
}  // namespace dt
