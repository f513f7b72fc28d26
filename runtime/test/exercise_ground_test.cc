// Tests [terrain] ground_file (docs/node.md "Starting from a saved terrain"): the exercise starts
// on the saved terrain with its features, the grid keys are refused beside it, a file that does
// not load is named, and the ground's source and digest are what every process builds.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "runtime/exercise_config.h"
#include "runtime/exercise_ground.h"
#include "runtime/test/exercise_config_samples.h"
#include "terrain/base_ground.h"
#include "terrain/feature.h"
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

}  // namespace
}  // namespace dt
