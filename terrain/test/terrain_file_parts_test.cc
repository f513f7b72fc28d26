// Tests ProbeTerrainFile and LoadTerrainFileFeatures: a terrain file read in parts (its shape
// without the ground, its features without the ground) says what LoadTerrain says of those parts,
// with the same refusals and offsets.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include "terrain/terrain_file.h"
#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

namespace fs = std::filesystem;

class TerrainFileParts : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "dt_terrain_parts_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    original_ = test::BuildSample(test::SampleFeatures());
    // Blade work: an earth move is a record of the file like any other.
    ASSERT_TRUE(original_->Add({3, 1, 1}, FeatureParams::EarthMove({{4, 4, -300}})).ok());
    bytes_ = EncodeTerrainFile(*original_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path Write(const std::vector<uint8_t>& b) {
    const fs::path path = dir_ / "t.dtt";
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    return path;
  }
  static void Reseal(std::vector<uint8_t>& b) {
    const size_t at = b.size() - 8;
    const uint64_t sum = XXH3_64bits(b.data(), at);
    for (size_t k = 0; k < 8; ++k) b[at + k] = static_cast<uint8_t>(sum >> (8 * k));
  }

  fs::path dir_;
  std::unique_ptr<Terrain> original_;
  std::vector<uint8_t> bytes_;
};

TEST_F(TerrainFileParts, TheProbeReadsTheShapeAndTheStoredChecksum) {
  const fs::path path = Write(bytes_);
  const Result<TerrainFileShape> shape = ProbeTerrainFile(path);
  ASSERT_TRUE(shape.ok()) << shape.error().message;
  EXPECT_EQ(shape.value().version, kSquareTerrainFileVersion);
  EXPECT_EQ(shape.value().posts_x, 9);
  EXPECT_EQ(shape.value().posts_z, 9);
  EXPECT_EQ(shape.value().spacing_m, 10.0);
  EXPECT_EQ(shape.value().file_bytes, bytes_.size());
  EXPECT_EQ(shape.value().checksum, XXH3_64bits(bytes_.data(), bytes_.size() - 8));
}

TEST_F(TerrainFileParts, TheFeaturesAreTheFilesRecordsInIdOrder) {
  const Result<std::vector<std::pair<FeatureId, FeatureParams>>> read =
      LoadTerrainFileFeatures(Write(bytes_));
  ASSERT_TRUE(read.ok()) << read.error().message;
  std::vector<std::pair<FeatureId, FeatureParams>> expected;
  for (const Feature* f : original_->FeaturesById()) expected.emplace_back(f->id(), f->params());
  ASSERT_EQ(expected.size(), test::SampleFeatures().size() + 1);
  EXPECT_EQ(read.value(), expected);
}

TEST_F(TerrainFileParts, EveryRefusalOfAPartIsLoadTerrainsOwn) {
  // Every truncation: the probe and the feature reader refuse it as LoadTerrain does (the
  // lengths in the header no longer match the size, or the file is shorter than a header).
  for (size_t size : {size_t{0}, size_t{20}, size_t{35}, bytes_.size() / 2, bytes_.size() - 1}) {
    std::vector<uint8_t> b(bytes_.begin(), bytes_.begin() + static_cast<ptrdiff_t>(size));
    const fs::path path = Write(b);
    const std::string whole = LoadTerrain(path).error().message;
    EXPECT_EQ(ProbeTerrainFile(path).error().message, whole) << size;
    EXPECT_EQ(LoadTerrainFileFeatures(path).error().message, whole) << size;
  }
  // Header and shape: the magic, the version, the post count, the spacing (resealed, so the
  // checksum LoadTerrain checks first passes).
  for (const auto& [at, value] :
       {std::pair<size_t, uint8_t>{1, 'x'}, {8, 99}, {28, 1}, {39, 0xFF}}) {
    std::vector<uint8_t> b = bytes_;
    b[at] = value;
    Reseal(b);
    const fs::path path = Write(b);
    const std::string whole = LoadTerrain(path).error().message;
    EXPECT_NE(whole.find(fmt::format("{}: byte ", path.string())), std::string::npos) << whole;
    EXPECT_EQ(ProbeTerrainFile(path).error().message, whole) << at;
    EXPECT_EQ(LoadTerrainFileFeatures(path).error().message, whole) << at;
  }
  // A feature record's length past the section: the feature reader names it as LoadTerrain does;
  // the probe, which reads no feature, does not.
  {
    std::vector<uint8_t> b = bytes_;
    const size_t records_at = 28 + 12 + 4 * 81 + 2 * 2 * 64 + 4;
    b[records_at + 8 + 3] = 0x40;
    Reseal(b);
    const fs::path path = Write(b);
    const std::string whole = LoadTerrain(path).error().message;
    EXPECT_NE(whole.find("feature section ends inside feature 1:1:1"), std::string::npos) << whole;
    EXPECT_EQ(LoadTerrainFileFeatures(path).error().message, whole);
    EXPECT_TRUE(ProbeTerrainFile(path).ok());
  }
  // A flipped post: only LoadTerrain reads the posts and the checksum over them.
  {
    std::vector<uint8_t> b = bytes_;
    b[28 + 12 + 40] ^= 0x01;
    const fs::path path = Write(b);
    EXPECT_NE(LoadTerrain(path).error().message.find("checksum mismatch"), std::string::npos);
    EXPECT_TRUE(ProbeTerrainFile(path).ok());
    EXPECT_TRUE(LoadTerrainFileFeatures(path).ok());
  }
}

}  // namespace
}  // namespace dt
