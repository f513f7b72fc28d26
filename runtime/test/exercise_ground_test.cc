// Tests [terrain] ground_file (docs/node.md "Starting from a saved terrain"): the exercise starts
// on the saved terrain with its features, the grid keys are refused beside it, a file that does
// not load is named, the ground's source and digest are what every process builds, the bare
// ground is shared through the host's ground cache, and a reader that skips the ground never
// opens the file.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "runtime/exercise_config.h"
#include "runtime/exercise_ground.h"
#include "runtime/test/exercise_config_samples.h"
#include "terrain/base_ground.h"
#include "terrain/feature.h"
#include "terrain/ground_cache.h"
#include "terrain/random_terrain.h"
#include "terrain/terrain_digest.h"
#include "terrain/terrain_file.h"

namespace dt {
namespace {

using test::ErrorOf;
using test::kGood;
using test::Replace;

class ExerciseGroundTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("dt-exercise-ground-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "grounds");
    // A 41 x 25 saved battlefield: random ground, blade work, a crater and a berm.
    saved_ = std::make_unique<Terrain>(
        MakeRandomTerrain({.posts_x = 41, .posts_z = 25, .spacing_m = 4.0, .seed = 3}));
    ASSERT_TRUE(saved_->Add({1, 1, 4}, FeatureParams::Crater(60, 40, 5)).ok());
    ASSERT_TRUE(saved_->Add({1, 2, 1}, FeatureParams::Berm(100, 50, 0.3, 20, 4, 2)).ok());
    ASSERT_TRUE(SaveTerrain(*saved_, dir_ / "grounds" / "field.dtt").ok());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // kGood with its [terrain] replaced by `terrain`, read as if from dir_/ex.toml.
  ExerciseConfig Parse(const std::string& terrain) {
    return ParseExerciseConfig(Text(terrain), (dir_ / "ex.toml").string(), dir_);
  }
  static std::string Text(const std::string& terrain) {
    return Replace(kGood, "posts_per_side = 65\nspacing_m = 5.0\nrelief_m = 20\nseed = 9", terrain);
  }

  std::filesystem::path dir_;
  std::unique_ptr<Terrain> saved_;
};

TEST_F(ExerciseGroundTest, AGroundFileExerciseStartsWithTheFilesGroundAndFeatures) {
  const ExerciseConfig c = Parse("ground_file = \"grounds/field.dtt\"");
  EXPECT_EQ(c.ground_file, dir_ / "grounds" / "field.dtt");
  EXPECT_EQ(c.terrain.posts_x, 41);
  EXPECT_EQ(c.terrain.posts_z, 25);
  EXPECT_DOUBLE_EQ(c.terrain_size_x_m(), 160.0);
  EXPECT_DOUBLE_EQ(c.terrain_size_z_m(), 96.0);
  const BaseGround ground = BuildExerciseGround(c);
  EXPECT_TRUE(std::ranges::equal(ground.grid.posts(), saved_->ground().posts()));
  ASSERT_EQ(ground.features.size(), 2u);
  // Renumbered under the ground's origin, in the order of their IDs, parameters unchanged.
  EXPECT_EQ(ground.features[0].first, (FeatureId{0, 0, 1}));
  EXPECT_EQ(ground.features[0].second, saved_->Find({1, 1, 4})->params());
  EXPECT_EQ(ground.features[1].second, saved_->Find({1, 2, 1})->params());
  // The surface is the saved one's, the crater and the berm on it.
  const std::unique_ptr<Terrain> t = MakeTerrain(ground);
  EXPECT_EQ(t->feature_count(), 2u);
  ASSERT_EQ(t->FeaturesNear(60, 40).size(), 1u);
  EXPECT_EQ(t->FeaturesNear(60, 40)[0]->type(), FeatureType::kCrater);
  for (double x = 40; x <= 120; x += 2.5) {
    EXPECT_DOUBLE_EQ(t->ElevationAt(x, 45), saved_->ElevationAt(x, 45)) << x;
  }
  EXPECT_NE(t->ElevationAt(100, 50), t->GroundElevationAt(100, 50));  // on the berm
  EXPECT_NE(ComputeDigest(ground), ComputeDigest(ground.grid));
  EXPECT_EQ(ExerciseGroundSource(c), "ground_file " + (dir_ / "grounds" / "field.dtt").string());
  // Every process built from the file has the same ground.
  EXPECT_EQ(ComputeDigest(BuildExerciseGround(Parse("ground_file = \"grounds/field.dtt\""))),
            ComputeDigest(ground));
}

TEST_F(ExerciseGroundTest, RandomGroundIsBuiltFromTheSeedWithoutFeatures) {
  const ExerciseConfig c = ParseExerciseConfig(kGood, "ex.toml", "/base");
  const BaseGround ground = BuildExerciseGround(c);
  EXPECT_TRUE(ground.features.empty());
  EXPECT_TRUE(std::ranges::equal(ground.grid.posts(), MakeRandomTerrain(c.terrain).posts()));
  EXPECT_EQ(ExerciseGroundSource(c), "random seed 9 65x65 posts spacing 5 m relief 20 m");
}

TEST_F(ExerciseGroundTest, AGroundFileAndAnElevationFileTogetherAreRefused) {
  const std::string e =
      ErrorOf(Text("ground_file = \"grounds/field.dtt\"\nelevation_file = \"dem.tif\""));
  EXPECT_NE(e.find("terrain.ground_file"), std::string::npos) << e;
  EXPECT_NE(e.find("not both"), std::string::npos) << e;
}

TEST_F(ExerciseGroundTest, GridKeysBesideAGroundFileAndABadFileAreRefusedByName) {
  std::string e = ErrorOf(Text("ground_file = \"grounds/field.dtt\"\nseed = 4"));
  EXPECT_NE(e.find("terrain.seed"), std::string::npos) << e;
  EXPECT_NE(e.find("the ground_file sets the ground"), std::string::npos) << e;
  e = ErrorOf(Text("ground_file = \"grounds/field.dtt\"\nposts_per_side = 65"));
  EXPECT_NE(e.find("terrain.posts_per_side"), std::string::npos) << e;

  EXPECT_THROW(Parse("ground_file = \"grounds/missing.dtt\""), std::invalid_argument);
  try {
    Parse("ground_file = \"grounds/missing.dtt\"");
  } catch (const std::invalid_argument& ex) {
    e = ex.what();
  }
  EXPECT_NE(e.find("terrain.ground_file"), std::string::npos) << e;
  EXPECT_NE(e.find((dir_ / "grounds" / "missing.dtt").string()), std::string::npos) << e;
}

// The message of the std::invalid_argument `f` throws, or "" if it throws none.
std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// The inodes of the files this process maps whose path is `path` (/proc/self/maps), one entry per
// mapping.
std::multiset<std::string> MappedInodes(const std::filesystem::path& path) {
  std::ifstream maps("/proc/self/maps");
  std::multiset<std::string> inodes;
  for (std::string line; std::getline(maps, line);) {
    std::istringstream fields(line);
    std::string range, perms, offset, device, inode, name;
    fields >> range >> perms >> offset >> device >> inode >> name;
    if (name == path.string()) inodes.insert(device + " " + inode);
  }
  return inodes;
}

// Overwrites `bytes` at `offset` of `path` and puts its modification time back, as if the file
// had not changed (no cache key notices).
void Overwrite(const std::filesystem::path& path, uint64_t offset, const std::string& bytes) {
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(offset));
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const timespec times[2] = {st.st_atim, st.st_mtim};
  ASSERT_EQ(utimensat(AT_FDCWD, path.c_str(), times, 0), 0);
}

TEST_F(ExerciseGroundTest, WithGroundCacheDirTheFilesGroundIsMappedFromOneCacheFile) {
  // Blade work too: its deltas are in the cached posts, and the earth move is no base feature.
  ASSERT_TRUE(saved_->Add({1, 3, 1}, FeatureParams::EarthMove({{5, 5, -400}, {6, 5, 250}})).ok());
  const std::filesystem::path field = dir_ / "grounds" / "field.dtt";
  ASSERT_TRUE(SaveTerrain(*saved_, field).ok());
  const BaseGround today = BaseGroundFromTerrain(*LoadTerrain(field).value());
  ASSERT_EQ(today.features.size(), 2u);

  const ExerciseConfig direct = Parse("ground_file = \"grounds/field.dtt\"");
  EXPECT_TRUE(GroundFileCacheDir(direct).empty());  // small: each process loads the file
  EXPECT_FALSE(BuildExerciseGround(direct).grid.is_mapped());
  const ExerciseConfig c =
      Parse("ground_file = \"grounds/field.dtt\"\nground_cache_dir = \"cache\"");
  EXPECT_EQ(GroundFileCacheDir(c), dir_ / "cache");
  const std::filesystem::path cache =
      GroundCacheFile(dir_ / "cache", GroundFileCacheKey(field, c.ground_file_shape->checksum));

  const BaseGround first = BuildExerciseGround(c);  // builds the cache file
  ASSERT_TRUE(std::filesystem::exists(cache));
  struct stat built {};
  ASSERT_EQ(stat(cache.c_str(), &built), 0);
  // The file's ground changed in place with its size and time kept: a process that maps the
  // cache reads only the file's feature section, so it still gets the cached posts.
  const float post0 = saved_->ground().post(0, 0);
  Overwrite(field, kTerrainFileHeaderBytes + 12, std::string(4, '\x7f'));
  const BaseGround second = BuildExerciseGround(c);
  struct stat mapped {};
  ASSERT_EQ(stat(cache.c_str(), &mapped), 0);
  EXPECT_EQ(mapped.st_ino, built.st_ino);  // not written again
  for (const BaseGround* g : {&first, &second}) {
    EXPECT_TRUE(g->grid.is_mapped());
    EXPECT_EQ(g->grid.post(0, 0), post0);
    EXPECT_TRUE(std::ranges::equal(g->grid.posts(), today.grid.posts()));
    EXPECT_EQ(g->features, today.features);
    EXPECT_EQ(ComputeDigest(*g), ComputeDigest(today));
  }
  // Both grids map the one cache file (one inode, two mappings), none holds a copy.
  const std::multiset<std::string> inodes = MappedInodes(cache);
  EXPECT_EQ(inodes.size(), 2u);
  EXPECT_EQ(std::set<std::string>(inodes.begin(), inodes.end()).size(), 1u);
  EXPECT_NE(inodes.begin()->find(" " + std::to_string(built.st_ino)), std::string::npos);
  // A process that loads the file whole sees the change: a damaged file, named with its offset.
  const std::string e = ErrorOf([&] { (void)BuildExerciseGround(direct); });
  EXPECT_NE(e.find("terrain.ground_file"), std::string::npos) << e;
  EXPECT_NE(e.find(field.string()), std::string::npos) << e;
  EXPECT_NE(e.find("checksum mismatch"), std::string::npos) << e;
}

TEST_F(ExerciseGroundTest, ADamagedGroundFileIsRefusedWhereTheGroundIsBuiltWithItsOffset) {
  const std::filesystem::path field = dir_ / "grounds" / "field.dtt";
  const std::string cached = "ground_file = \"grounds/field.dtt\"\nground_cache_dir = \"cache\"";
  // A post made NaN and the checksum made to match would be refused at the post; a flipped byte
  // is refused by the checksum, at its offset, before any cache file is written.
  Overwrite(field, kTerrainFileHeaderBytes + 20, "\x01");
  const ExerciseConfig c = Parse(cached);  // the header is sound
  const std::string e = ErrorOf([&] { (void)BuildExerciseGround(c); });
  EXPECT_NE(e.find("terrain.ground_file"), std::string::npos) << e;
  EXPECT_NE(e.find(field.string()), std::string::npos) << e;
  EXPECT_NE(
      e.find(fmt::format("byte {}: checksum mismatch", std::filesystem::file_size(field) - 8)),
      std::string::npos)
      << e;
  EXPECT_FALSE(std::filesystem::exists(
      GroundCacheFile(dir_ / "cache", GroundFileCacheKey(field, c.ground_file_shape->checksum))));
  // A damaged header is refused when the exercise file is read, naming the offset.
  Overwrite(field, 0, "X");
  const std::string h = ErrorOf([&] { (void)Parse(cached); });
  EXPECT_NE(h.find("byte 0: not a dynterrain terrain file"), std::string::npos) << h;
}

TEST_F(ExerciseGroundTest, SkippingTheGroundNeverOpensTheGroundFile) {
  const std::string text = Text("ground_file = \"grounds/gone.dtt\"");
  // A vehicle far beyond any ground of this size: its place is not checked without the ground.
  const std::string far = Replace(text, "x_m = 10\nz_m = 20.5", "x_m = 1e6\nz_m = 1e6");
  for (const std::string& t : {text, far}) {
    const ExerciseConfig c =
        ParseExerciseConfig(t, (dir_ / "ex.toml").string(), dir_, GroundReading::kSkip);
    EXPECT_FALSE(c.ground_read);
    EXPECT_FALSE(c.ground_file_shape.has_value());
    EXPECT_EQ(c.ground_file, dir_ / "grounds" / "gone.dtt");
    EXPECT_NE(c.FindProcess("node-1"), nullptr);
    EXPECT_EQ(c.SocketPath("node-1").filename(), "node-1.sock");
  }
  EXPECT_THROW(Parse("ground_file = \"grounds/gone.dtt\""), std::invalid_argument);
}

}  // namespace
}  // namespace dt
