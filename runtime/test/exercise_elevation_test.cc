// [terrain] elevation_file in an exercise file: the ground every process makes from it, the
// [dis] origin taken from the file (a typed one must agree to 1 m), and its errors.
#include "runtime/exercise_ground.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geo/test/test_rasters.h"
#include "runtime/exercise_config.h"
#include "terrain/ground_cache.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

constexpr double kE0 = 500000.0, kN0 = 5200000.0;
double Surface(double e, double n) { return 50.0 + 0.02 * (e - kE0) + 0.01 * (n - kN0); }

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

class ExerciseElevationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshTestDir("exercise_ground_test");
    testing::TestRaster r;
    r.cols = 41;
    r.rows = 31;
    r.geotransform = {kE0, 10, 0, kN0 + 310, 0, -10};
    r.surface = Surface;
    r.nodata = -9999.0;
    r.holes = {{3, 30}};  // post (3, 0)
    testing::WriteTestRaster(dir_ / "ground.tif", r);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // An exercise on ground.tif with `terrain` and `dis` lines added to its tables.
  ExerciseConfig Parse(const std::string& terrain, const std::string& dis = "") const {
    const std::string text = fmt::format(
        R"(
[exercise]
name = "g"
[auth]
mode = "none"
[terrain]
elevation_file = "ground.tif"
{}
[server]
name = "server"
site = 1
host = 1
[[node]]
name = "node-1"
site = 1
host = 2
{}
)",
        terrain, dis.empty() ? "" : "[dis]\nname = \"dis\"\nsite = 1\nhost = 9\n" + dis);
    return ParseExerciseConfig(text, "g.toml", dir_);
  }

  std::filesystem::path dir_;
};

TEST_F(ExerciseElevationTest, EveryProcessGetsTheFilesGround) {
  const ExerciseConfig c = Parse("nodata_fill = \"nearest\"");
  ASSERT_TRUE(c.elevation.has_value());
  EXPECT_EQ(c.elevation->source.file, dir_ / "ground.tif");
  EXPECT_EQ(c.terrain.posts_x, 41);
  EXPECT_EQ(c.terrain.posts_z, 31);
  EXPECT_DOUBLE_EQ(c.terrain_size_x_m(), 400.0);
  const HeightGrid a = BuildExerciseGround(c).grid;
  const HeightGrid b = BuildExerciseGround(c).grid;
  EXPECT_TRUE(std::ranges::equal(a.posts(), b.posts()));
  EXPECT_NEAR(a.post(20, 10), Surface(kE0 + 205, kN0 + 105), 1e-4);
  EXPECT_EQ(a.post(3, 0), a.post(2, 0));  // filled from its west neighbour
}

TEST_F(ExerciseElevationTest, WithGroundCacheDirTheGroundIsMappedFromOneFileWithTheSameDigest) {
  const ExerciseConfig direct = Parse("nodata_fill = \"nearest\"");
  EXPECT_TRUE(GroundCacheDir(*direct.elevation).empty());  // small: each process reads the file
  const ExerciseConfig c = Parse("nodata_fill = \"nearest\"\nground_cache_dir = \"cache\"");
  EXPECT_EQ(GroundCacheDir(*c.elevation), dir_ / "cache");
  const BaseGround from_file = BuildExerciseGround(direct);
  EXPECT_FALSE(from_file.grid.is_mapped());
  const BaseGround first = BuildExerciseGround(c);
  const std::filesystem::path file = GroundCacheFile(dir_ / "cache", GroundCacheKey(*c.elevation));
  ASSERT_TRUE(std::filesystem::exists(file));
  // Opening marks the file used (its modification time), so the inode tells a rebuild: a new
  // file is renamed into place.
  auto inode = [&] {
    struct stat st {};
    EXPECT_EQ(stat(file.c_str(), &st), 0);
    return st.st_ino;
  };
  const auto written = inode();
  const BaseGround second = BuildExerciseGround(c);
  EXPECT_EQ(inode(), written);  // mapped, not written again
  for (const BaseGround* g : {&first, &second}) {
    EXPECT_TRUE(g->grid.is_mapped());
    EXPECT_EQ(ComputeDigest(*g), ComputeDigest(from_file));
  }
  // Another fill is another ground: another file.
  const ExerciseConfig other =
      Parse("nodata_fill = \"constant\"\nnodata_fill_m = 3\nground_cache_dir = \"cache\"");
  EXPECT_NE(GroundCacheKey(*other.elevation), GroundCacheKey(*c.elevation));
  // The key is refused without an elevation file like the other elevation keys.
  EXPECT_NE(std::find(kElevationKeys.begin(), kElevationKeys.end(), "ground_cache_dir"),
            kElevationKeys.end());
}

TEST_F(ExerciseElevationTest, NodataWithoutAFillIsAnErrorAtStart) {
  const ExerciseConfig c = Parse("");
  const std::string e = ErrorOf([&] { (void)BuildExerciseGround(c); });
  EXPECT_NE(e.find("1 of the 41 x 31 posts have no data"), std::string::npos) << e;
  EXPECT_NE(e.find("post (3, 0) at x 30 m z 0 m"), std::string::npos) << e;
}

TEST_F(ExerciseElevationTest, RandomGroundKeysDoNotMixWithAFile) {
  EXPECT_NE(ErrorOf([&] { Parse("seed = 3"); }).find("elevation_file gives the ground"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { Parse("resampling = \"nearest\""); }).find("\"bilinear\" or \"cubic\""),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { Parse("nodata_fill = \"constant\""); }).find("needs nodata_fill_m"),
            std::string::npos);
  const std::string e =
      ErrorOf([&] { Parse("area_crs = [[500100, 5200100], [500050, 5200200]]"); });
  EXPECT_NE(e.find("south-west of the second"), std::string::npos) << e;
}

TEST_F(ExerciseElevationTest, WindowAndSpacingKeys) {
  const ExerciseConfig c = Parse(
      "area_crs = [[500105, 5200105], [500305, 5200205]]\nspacing_m = 5\nresampling = "
      "\"cubic\"");
  EXPECT_EQ(c.terrain.posts_x, 41);
  EXPECT_EQ(c.terrain.posts_z, 21);
  EXPECT_EQ(c.elevation->source.resampling, Resampling::kCubic);
  const HeightGrid g = BuildExerciseGround(c).grid;
  EXPECT_NEAR(g.post(7, 3), Surface(kE0 + 105 + 35, kN0 + 105 + 15), 1e-3);  // a plane: exact
}

TEST_F(ExerciseElevationTest, TheDisOriginIsTheFilesAndATypedOneMustAgree) {
  const ExerciseConfig c = Parse("nodata_fill = \"nearest\"", "udp_port = 3001\n");
  const GeodeticPoint o = c.elevation->layout.georeference->origin();
  ASSERT_TRUE(c.dis.has_value());
  EXPECT_EQ(c.dis->latitude_deg, o.latitude_deg);
  EXPECT_EQ(c.dis->longitude_deg, o.longitude_deg);
  EXPECT_EQ(c.dis->height_m, 0.0);
  // Typed to 1e-6 deg (0.11 m of latitude): agrees.
  const std::string close = fmt::format("latitude_deg = {:.6f}\nlongitude_deg = {:.6f}\n",
                                        o.latitude_deg, o.longitude_deg);
  EXPECT_NO_THROW(Parse("nodata_fill = \"nearest\"", close));
  // 0.0001 deg of latitude is 11 m off.
  const std::string far = fmt::format("latitude_deg = {:.6f}\nlongitude_deg = {:.6f}\n",
                                      o.latitude_deg + 1e-4, o.longitude_deg);
  const std::string e = ErrorOf([&] { Parse("nodata_fill = \"nearest\"", far); });
  EXPECT_NE(e.find("lie 11."), std::string::npos) << e;
  EXPECT_NE(e.find("ground.tif"), std::string::npos) << e;
  EXPECT_NE(e.find("more than 1 m"), std::string::npos) << e;
  // A height alone counts too: 2 m up.
  EXPECT_NE(ErrorOf([&] {
              Parse("nodata_fill = \"nearest\"", close + "height_m = 2\n");
            }).find("more than 1 m"),
            std::string::npos);
}

TEST_F(ExerciseElevationTest, AnUnreadableFileIsAConfigErrorNamingIt) {
  std::ofstream(dir_ / "ground.tif", std::ios::trunc) << "junk";
  const std::string e = ErrorOf([&] { Parse(""); });
  EXPECT_NE(e.find("g.toml: terrain.elevation_file"), std::string::npos) << e;
  EXPECT_NE(e.find((dir_ / "ground.tif").string()), std::string::npos) << e;
  EXPECT_NE(e.find("not recognized"), std::string::npos) << e;
}

}  // namespace
}  // namespace dt
