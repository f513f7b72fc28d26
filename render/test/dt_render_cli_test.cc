#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "render/image_diff.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "terrain/random_terrain.h"
#include "terrain/terrain_file.h"

namespace dt {
namespace {

// Runs the dt_render binary (path given by the build) with `args`; returns its exit status.
int RunCli(const std::string& args) {
  const std::string cmd = std::string(DT_RENDER_CLI_PATH) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class DtRenderCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("dt_render_cli_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    RandomTerrainParams p;
    p.posts_x = p.posts_z = 33;
    p.spacing_m = 4.0;
    p.relief_m = 8.0;
    terrain_ = std::make_unique<Terrain>(MakeRandomTerrain(p));
    ASSERT_TRUE(terrain_->Add({1, 1, 1}, FeatureParams::Crater(50.0, 60.0, 12.0)).ok());
    ASSERT_TRUE(SaveTerrain(*terrain_, Path("t.dtt")).ok());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
  std::unique_ptr<Terrain> terrain_;
};

TEST_F(DtRenderCliTest, MapOfASavedFileMatchesTheLibrary) {
  ASSERT_EQ(RunCli(Path("t.dtt") + " -o " + Path("map.png") + " --width 128"), 0);
  const Result<Image> png = ReadPng(Path("map.png"));
  ASSERT_TRUE(png.ok()) << png.error().message;
  Renderer r;
  const Image direct = r.Render(*terrain_, {}, Camera::MapOf({0, 0, 128, 128}, 128));
  EXPECT_EQ(DiffImages(png.value(), direct).differing_pixels, 0u);
}

TEST_F(DtRenderCliTest, PerspectiveWithVehiclesWrites) {
  ASSERT_EQ(RunCli(Path("t.dtt") + " -o " + Path("p.png") +
                   " --camera perspective --width 160 --height 120 --eye -20,60,-20"
                   " --target 64,0,64 --grid-m 32 --vehicle 40,40,30 --vehicle 80,80,0,5,-5"),
            0);
  const Result<Image> png = ReadPng(Path("p.png"));
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png.value().width(), 160);
  EXPECT_EQ(png.value().height(), 120);
}

// A ground 128 m east by 32 m north: the map is four times as wide as high, and matches the
// library's; the default perspective frames it too.
TEST_F(DtRenderCliTest, ARectangularTerrainKeepsItsAspect) {
  RandomTerrainParams p;
  p.posts_x = 33;
  p.posts_z = 9;
  p.spacing_m = 4.0;
  p.relief_m = 8.0;
  Terrain rect(MakeRandomTerrain(p));
  ASSERT_TRUE(rect.Add({1, 1, 1}, FeatureParams::Crater(120.0, 24.0, 6.0)).ok());
  ASSERT_TRUE(SaveTerrain(rect, Path("rect.dtt")).ok());
  ASSERT_EQ(RunCli(Path("rect.dtt") + " -o " + Path("rect.png") + " --width 128"), 0);
  const Result<Image> png = ReadPng(Path("rect.png"));
  ASSERT_TRUE(png.ok()) << png.error().message;
  EXPECT_EQ(png.value().width(), 128);
  EXPECT_EQ(png.value().height(), 32);
  Renderer r;
  const Image direct = r.Render(rect, {}, Camera::MapOf({0, 0, 128, 32}, 128));
  EXPECT_EQ(DiffImages(png.value(), direct).differing_pixels, 0u);
  // A vehicle past the north edge (inside a 128 m square) is refused.
  EXPECT_EQ(RunCli(Path("rect.dtt") + " -o " + Path("x.png") + " --vehicle 60,60,0"), 1);
  EXPECT_EQ(RunCli(Path("rect.dtt") + " -o " + Path("p.png") +
                   " --camera perspective --width 160 --height 120 --vehicle 100,20,0"),
            0);
  EXPECT_TRUE(ReadPng(Path("p.png")).ok());
}

TEST_F(DtRenderCliTest, BadInputFailsWithoutWriting) {
  EXPECT_EQ(RunCli(Path("missing.dtt") + " -o " + Path("x.png")), 1);
  EXPECT_EQ(RunCli(Path("t.dtt") + " -o " + Path("x.png") + " --vehicle 500,500,0"), 1);
  EXPECT_EQ(RunCli(Path("t.dtt") + " -o " + Path("x.png") + " --vehicle 1,2"), 1);
  EXPECT_FALSE(std::filesystem::exists(Path("x.png")));
  EXPECT_EQ(RunCli(Path("t.dtt") + " -o " + Path("x.png") + " --camera sideways"), 2);
  EXPECT_EQ(RunCli(Path("t.dtt")), 2);
}

}  // namespace
}  // namespace dt
