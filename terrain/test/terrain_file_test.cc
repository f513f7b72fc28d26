#include "terrain/terrain_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include "base/bytes.h"
#include "terrain/terrain_digest.h"
#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

namespace fs = std::filesystem;
using test::BuildSample;
using test::SampleFeatures;

// Offsets of docs/terrain-file-format.md for the 9 x 9 sample.
constexpr size_t kGroundAt = 28;
constexpr size_t kPostsAt = kGroundAt + 12;
constexpr size_t kSoilsAt = kPostsAt + 4 * 81;
constexpr size_t kFeaturesAt = kSoilsAt + 2 * 2 * 64;

std::unique_ptr<Terrain> Sample() {
  auto t = BuildSample(SampleFeatures());
  // Soils other than the default, so the soil section carries information.
  EXPECT_TRUE(t->SetSoil({0, 0}, TriangleHalf::kUpper, Material::kRock).ok());
  EXPECT_TRUE(t->SetSoil({7, 7}, TriangleHalf::kLower, Material::kAsphalt).ok());
  return t;
}

// Recomputes the trailing checksum after a deliberate edit, to reach the checks behind it.
void Reseal(std::vector<uint8_t>& bytes) {
  const size_t at = bytes.size() - 8;
  const uint64_t sum = XXH3_64bits(bytes.data(), at);
  for (size_t k = 0; k < 8; ++k) bytes[at + k] = static_cast<uint8_t>(sum >> (8 * k));
}

void PutU32(std::vector<uint8_t>& bytes, size_t at, uint32_t v) {
  // The bound check also keeps GCC 12 from a false -Wstringop-overflow under -O2.
  if (at > bytes.size() || bytes.size() - at < 4) std::abort();
  for (size_t k = 0; k < 4; ++k) bytes[at + k] = static_cast<uint8_t>(v >> (8 * k));
}

void ExpectRefused(std::span<const uint8_t> bytes, const std::string& fragment) {
  const auto r = DecodeTerrainFile(bytes, "t.dtt");
  ASSERT_FALSE(r.ok()) << "expected: " << fragment;
  EXPECT_NE(r.error().message.find("t.dtt: byte "), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find(fragment), std::string::npos)
      << "message: " << r.error().message << "\nexpected fragment: " << fragment;
}

class TerrainFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "dt_terrain_file_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST(TerrainFileTest, DecodeRebuildsTheSameState) {
  const auto original = Sample();
  const auto bytes = EncodeTerrainFile(*original);
  auto loaded = DecodeTerrainFile(bytes, "mem");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const Terrain& t = *loaded.value();
  EXPECT_EQ(ComputeDigest(t), ComputeDigest(*original));
  EXPECT_TRUE(std::ranges::equal(t.ground().posts(), original->ground().posts()));
  EXPECT_TRUE(std::ranges::equal(t.ground().soils(), original->ground().soils()));
  EXPECT_EQ(t.ground().spacing_m(), 10.0);
  ASSERT_EQ(t.feature_count(), SampleFeatures().size());
  for (const auto& [id, params] : SampleFeatures()) {
    ASSERT_NE(t.Find(id), nullptr) << id.ToString();
    EXPECT_EQ(t.Find(id)->params(), original->Find(id)->params()) << id.ToString();
  }
  // Encoding is canonical: the loaded terrain encodes to the same bytes.
  EXPECT_EQ(EncodeTerrainFile(t), bytes);
}

TEST_F(TerrainFiles, SaveThenLoadKeepsTheDigestAndLeavesNoTemporaryFile) {
  const auto original = Sample();
  const fs::path path = dir_ / "exercise.dtt";
  ASSERT_TRUE(SaveTerrain(Terrain(HeightGrid(3, 1.0)), path).ok());
  // Saving again replaces the file whole.
  const Status saved = SaveTerrain(*original, path);
  ASSERT_TRUE(saved.ok()) << saved.error().message;
  auto loaded = LoadTerrain(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(ComputeDigest(*loaded.value()), ComputeDigest(*original));
  std::vector<fs::path> entries(fs::directory_iterator(dir_), fs::directory_iterator{});
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].filename(), "exercise.dtt");
  EXPECT_EQ(fs::file_size(path), EncodeTerrainFile(*original).size());
}

TEST_F(TerrainFiles, SaveAndLoadReportFileSystemErrors) {
  const auto missing = LoadTerrain(dir_ / "absent.dtt");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("absent.dtt: cannot open"), std::string::npos);
  const Status s = SaveTerrain(*Sample(), dir_ / "no_such_dir" / "t.dtt");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("cannot create a temporary file"), std::string::npos)
      << s.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
}

TEST_F(TerrainFiles, SaveRefusesToReplaceWhatIsNotARegularFile) {
  // A directory would fail the final rename; a FIFO would silently become a regular file.
  fs::create_directory(dir_ / "taken");
  std::ofstream(dir_ / "taken" / "keep") << "x";
  ASSERT_EQ(mkfifo((dir_ / "pipe").c_str(), 0600), 0);
  for (const auto& [name, kind] :
       {std::pair{"taken", "a directory"}, std::pair{"pipe", "a FIFO"}}) {
    const Status s = SaveTerrain(*Sample(), dir_ / name);
    ASSERT_FALSE(s.ok()) << name;
    EXPECT_NE(s.error().message.find((dir_ / name).string() + ": is " + kind), std::string::npos)
        << s.error().message;
  }
  EXPECT_TRUE(fs::is_fifo(dir_ / "pipe"));
  EXPECT_TRUE(fs::exists(dir_ / "taken" / "keep"));
  std::vector<fs::path> entries(fs::directory_iterator(dir_), fs::directory_iterator{});
  EXPECT_EQ(entries.size(), 2u);  // no temporary file left
}

// Each refused before a byte is decoded, with the path and the reason; none may block or throw.
TEST_F(TerrainFiles, LoadRefusesWhatIsNotARegularFileOfBoundedSize) {
  fs::create_directory(dir_ / "dir.dtt");
  ASSERT_EQ(mkfifo((dir_ / "fifo.dtt").c_str(), 0600), 0);  // no writer: a blocking open waits
  { std::ofstream big(dir_ / "big.dtt"); }
  fs::resize_file(dir_ / "big.dtt", kMaxTerrainFileBytes + 1);  // sparse: costs no disk
  const std::pair<fs::path, std::string> cases[] = {
      {dir_ / "dir.dtt", "is a directory, not a regular file"},
      {dir_ / "fifo.dtt", "is a FIFO, not a regular file"},
      {"/dev/zero", "is a character device, not a regular file"},
      {dir_ / "big.dtt", fmt::format("is {} bytes, over the limit of {} bytes",
                                     kMaxTerrainFileBytes + 1, kMaxTerrainFileBytes)},
  };
  for (const auto& [path, reason] : cases) {
    const auto r = LoadTerrain(path);
    ASSERT_FALSE(r.ok()) << path;
    EXPECT_EQ(r.error().message, path.string() + ": " + reason);
  }
}

TEST_F(TerrainFiles, LoadRefusesEmptyAndTruncatedFiles) {
  std::ofstream(dir_ / "empty.dtt").close();
  const auto empty = LoadTerrain(dir_ / "empty.dtt");
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().message.find("empty.dtt: byte 0: file is 0 bytes"), std::string::npos)
      << empty.error().message;
  const auto bytes = EncodeTerrainFile(*Sample());
  {
    std::ofstream out(dir_ / "cut.dtt", std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size() / 2));
  }
  const auto cut = LoadTerrain(dir_ / "cut.dtt");
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().message.find("cut.dtt: byte 12: header declares"), std::string::npos)
      << cut.error().message;
}

TEST(TerrainFileTest, EveryTruncationIsRefused) {
  const auto bytes = EncodeTerrainFile(*Sample());
  for (size_t length = 0; length < bytes.size(); ++length) {
    SCOPED_TRACE(length);
    ASSERT_FALSE(DecodeTerrainFile(std::span(bytes).first(length), "t.dtt").ok());
  }
  auto longer = bytes;
  longer.push_back(0);
  ExpectRefused(longer, "does not match the file size");
}

TEST(TerrainFileTest, EveryFlippedByteIsRefused) {
  const auto bytes = EncodeTerrainFile(*Sample());
  for (size_t at = 0; at < bytes.size(); ++at) {
    for (uint8_t mask : {uint8_t{0x01}, uint8_t{0x80}, uint8_t{0xFF}}) {
      auto corrupt = bytes;
      corrupt[at] ^= mask;
      const auto r = DecodeTerrainFile(corrupt, "t.dtt");
      ASSERT_FALSE(r.ok()) << "byte " << at << " mask " << int{mask};
    }
  }
  // Past the header, corruption is caught by the checksum.
  auto corrupt = bytes;
  corrupt[kPostsAt + 5] ^= 0x10;
  ExpectRefused(corrupt, "checksum mismatch");
}

TEST(TerrainFileTest, HeaderErrorsNameWhatFailed) {
  const auto bytes = EncodeTerrainFile(*Sample());
  ExpectRefused(std::span(bytes).first(35), "byte 35: file is 35 bytes, shorter than");
  auto magic = bytes;
  magic[1] = 'X';
  ExpectRefused(magic, "byte 0: not a dynterrain terrain file");
  auto version = bytes;
  PutU32(version, 8, 5);
  Reseal(version);
  ExpectRefused(version,
                "byte 8: format version 5 is not supported (this build reads versions 1 "
                "to 4)");
  PutU32(version, 8, 0);
  Reseal(version);
  ExpectRefused(version, "byte 8: format version 0 is not supported");
  auto lengths = bytes;
  PutU32(lengths, 12, 4);  // ground section length, now too short for any grid
  ExpectRefused(lengths, "byte 12: header declares a 4-byte ground section");
}

// A version 1 file, written byte by byte from the layout docs/terrain-file-format.md gave for
// version 1 (not by this build's writer): a 3 x 3 ground with a crater and a berm.
std::vector<uint8_t> VersionOneFile(uint16_t feature_type = 1) {
  ByteWriter ground;
  ground.U32(3);
  ground.F64(10.0);
  for (int k = 0; k < 9; ++k) ground.F32(static_cast<float>(k));
  for (int k = 0; k < 8; ++k) ground.U16(k % 2 ? 2 : 3);  // dirt, sand
  ByteWriter features;
  features.U32(2);
  auto record = [&](uint32_t number, uint16_t type, std::array<double, 9> fields) {
    features.U16(1);
    features.U16(2);
    features.U32(number);
    features.U32(82);  // the version 1 parameter record: no points
    features.U16(type);
    for (double v : fields) features.F64(v);  // x, z, direction, height[2], length[3], width
    features.U16(0);                          // material: from the ground
    features.I32(0);                          // status
    features.U16(0);                          // no vertex edits
  };
  record(1, feature_type, {10, 10, 0, 0, 0, 4, 0, 0, 0});
  record(2, 2, {2, 5, 0, 1.5, 0, 15, 0, 0, 3});
  ByteWriter file;
  for (uint8_t b : std::array<uint8_t, 8>{0x89, 'D', 'T', 'E', 'R', '\r', '\n', 0x1A}) file.U8(b);
  file.U32(1);
  file.U64(ground.bytes().size());
  file.U64(features.bytes().size());
  file.Bytes(ground.bytes());
  file.Bytes(features.bytes());
  file.U64(XXH3_64bits(file.bytes().data(), file.bytes().size()));
  return file.bytes();
}

TEST(TerrainFileTest, VersionOneFilesStillLoad) {
  const auto bytes = VersionOneFile();
  auto loaded = DecodeTerrainFile(bytes, "old.dtt");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  std::vector<float> posts;
  for (int k = 0; k < 9; ++k) posts.push_back(static_cast<float>(k));
  HeightGrid ground(3, 10.0, std::move(posts));
  Terrain expected(ground);
  for (int k = 0; k < 8; ++k) {
    ASSERT_TRUE(expected
                    .SetSoil({(k / 2) % 2, k / 4},
                             k % 2 ? TriangleHalf::kUpper : TriangleHalf::kLower,
                             k % 2 ? Material::kDirt : Material::kSand)
                    .ok());
  }
  ASSERT_TRUE(expected.Add({1, 2, 1}, FeatureParams::Crater(10, 10, 4)).ok());
  ASSERT_TRUE(expected.Add({1, 2, 2}, FeatureParams::Berm(2, 5, 0, 15, 3, 1.5)).ok());
  EXPECT_EQ(ComputeDigest(*loaded.value()), ComputeDigest(expected));
  // Saved again, it is a version 3 file of the same state.
  const auto again = EncodeTerrainFile(*loaded.value());
  EXPECT_EQ(again[8], 3);
  EXPECT_EQ(ComputeDigest(*DecodeTerrainFile(again, "new.dtt").value()), ComputeDigest(expected));
}

TEST(TerrainFileTest, VersionOneCannotHoldTheNewTypes) {
  ExpectRefused(VersionOneFile(4), "a version 1 file cannot hold a ditch");
}

TEST(TerrainFileTest, EveryNewTypeSurvivesARoundTrip) {
  Terrain t(HeightGrid(33, 2.0, 1.0f, Material::kGrass));
  ASSERT_TRUE(t.Add({1, 1, 1}, FeatureParams::DeepCrater(20, 20, 6, 2.5)).ok());
  ASSERT_TRUE(
      t.Add({1, 1, 2}, FeatureParams::Ditch({{9, 40, 2, 5}, {30, 40, 1.5, 4}, {40, 55, 2, 5}}, 1.0,
                                            1.0, 2.0, Material::kDirt))
          .ok());
  ASSERT_TRUE(t.Add({1, 1, 3}, FeatureParams::BermLine({{40, 5, 1, 4}, {55, 10, 2, 6}})).ok());
  ASSERT_TRUE(t.Add({1, 1, 4}, FeatureParams::Area({{10, 10, 0, 0}, {30, 10, 0, 0}, {20, 30, 0, 0}},
                                                   Material::kWater, 0.5))
                  .ok());
  auto back = DecodeTerrainFile(EncodeTerrainFile(t), "t.dtt");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(ComputeDigest(*back.value()), ComputeDigest(t));
  for (const Feature* f : t.FeaturesById()) {
    EXPECT_EQ(back.value()->Find(f->id())->params(), f->params()) << f->id().ToString();
  }
}

TEST(TerrainFileTest, ResealedStructuralErrorsAreStillRefused) {
  const auto bytes = EncodeTerrainFile(*Sample());
  {
    auto b = bytes;
    PutU32(b, kGroundAt, 10);  // 10 x 10 posts do not fit the 9 x 9 section
    Reseal(b);
    ExpectRefused(b, "byte 12: ground section is 592 bytes but a 10 x 10 grid needs 736");
  }
  {
    auto b = bytes;
    PutU32(b, kGroundAt, 1);
    Reseal(b);
    ExpectRefused(
        b, fmt::format("byte 28: posts_per_side 1 is outside [2, {}]", kMaxGridPostsPerSide));
  }
  {
    auto b = bytes;
    const double bad = -1.0;
    const uint64_t bits = std::bit_cast<uint64_t>(bad);
    for (size_t k = 0; k < 8; ++k) b[kGroundAt + 4 + k] = static_cast<uint8_t>(bits >> (8 * k));
    Reseal(b);
    ExpectRefused(b, "byte 32: spacing_m -1 must be finite and > 0");
  }
  {
    auto b = bytes;
    PutU32(b, kPostsAt + 4 * (2 * 9 + 3),
           std::bit_cast<uint32_t>(std::numeric_limits<float>::quiet_NaN()));
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: post (3, 2) is not finite", kPostsAt + 4 * 21));
  }
  {
    auto b = bytes;
    b[kSoilsAt + 2 * 5] = 0;  // square (2, 0), upper half: "from_ground" is no soil
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: soil 0 of square (2, 0) is not a soil", kSoilsAt + 10));
  }
  {
    auto b = bytes;
    PutU32(b, kFeaturesAt, 99);  // more records claimed than present
    Reseal(b);
    ExpectRefused(b, "feature section ends inside the header of feature record 6 of 99");
  }
  {
    auto b = bytes;
    PutU32(b, kFeaturesAt, 4);  // one record fewer claimed than present
    Reseal(b);
    ExpectRefused(b, "bytes left over after the last feature");
  }
  {
    // The first record is 1:1:1; renumbering it 1:1:5 breaks the order.
    auto b = bytes;
    PutU32(b, kFeaturesAt + 4 + 4, 5);
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: feature 1:1:2 follows 1:1:5", kFeaturesAt + 4 + 12 +
                                                                             /*crater record*/ 82));
  }
  {
    auto b = bytes;
    b[kFeaturesAt + 4] = 0;  // origin 0:1 (0:0 alone is allowed: the base ground's origin)
    b[kFeaturesAt + 4 + 1] = 0;
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: feature 0:1:1: origin site is 0, which is no node's",
                                 kFeaturesAt + 4));
  }
  {
    // The base ground's origin 0:0 (terrain/base_ground.h) loads.
    auto b = bytes;
    PutU32(b, kFeaturesAt + 4, 0);
    Reseal(b);
    auto loaded = DecodeTerrainFile(b, "base");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_NE(loaded.value()->Find({0, 0, 1}), nullptr);
  }
  {
    auto b = bytes;
    b[kFeaturesAt + 4 + 2] = 0;  // origin 1:0
    b[kFeaturesAt + 4 + 3] = 0;
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: feature 1:0:1: origin host is 0, which is no node's",
                                 kFeaturesAt + 4 + 2));
  }
  {
    // Number 0 means "no feature".
    auto b = bytes;
    PutU32(b, kFeaturesAt + 4 + 4, 0);
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: feature 1:1:0 was refused", kFeaturesAt + 4));
  }
  {
    // Move the first crater's x to 79 m: its rim leaves the 80 m terrain.
    auto b = bytes;
    const uint64_t bits = std::bit_cast<uint64_t>(79.0);
    const size_t x_at = kFeaturesAt + 4 + 12 + 2;
    for (size_t k = 0; k < 8; ++k) b[x_at + k] = static_cast<uint8_t>(bits >> (8 * k));
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: feature 1:1:1 was refused", kFeaturesAt + 4));
  }
  {
    // A crater radius of -3 fails parameter decoding.
    auto b = bytes;
    const uint64_t bits = std::bit_cast<uint64_t>(-3.0);
    const size_t radius_at = kFeaturesAt + 4 + 12 + 2 + 8 * 5;
    for (size_t k = 0; k < 8; ++k) b[radius_at + k] = static_cast<uint8_t>(bits >> (8 * k));
    Reseal(b);
    ExpectRefused(
        b, fmt::format("byte {}: feature 1:1:1: feature record at byte 0", kFeaturesAt + 4 + 12));
  }
  {
    // A record length one byte longer than its parameters.
    auto b = bytes;
    PutU32(b, kFeaturesAt + 4 + 8, 82 + 1);
    Reseal(b);
    ExpectRefused(b, "feature 1:1:1: 1 bytes left over after its parameters");
  }
}

TEST(TerrainFileTest, ConflictingFeaturesInAResealedFileAreRefused) {
  // Each record is valid alone, but a second bridge on the first one's deck is refused by
  // Terrain::Add, so the whole file is.
  Terrain one(test::SampleGround());
  const FeatureParams bridge = SampleFeatures()[4].second;
  ASSERT_TRUE(one.Add({1, 1, 9}, bridge).ok());
  auto b = EncodeTerrainFile(one);
  const size_t features_at = kFeaturesAt;
  const size_t record_at = features_at + 4;
  const size_t record_bytes = b.size() - 8 - record_at;
  std::vector<uint8_t> second(b.begin() + record_at, b.begin() + record_at + record_bytes);
  PutU32(second, 4, 10);  // id 1:1:10
  b.insert(b.end() - 8, second.begin(), second.end());
  PutU32(b, features_at, 2);
  PutU32(b, 20, static_cast<uint32_t>(4 + 2 * record_bytes));  // feature section length
  Reseal(b);
  ExpectRefused(b, fmt::format("byte {}: feature 1:1:10 was refused: bridge 1:1:10 overlaps",
                               record_at + record_bytes));
}

// ---- Rectangular grounds: version 4 ----

// A 9 x 4 ground (80 m x 30 m) with distinct posts and soils, a crater at the far x and z edges, a
// ditch along the far z edge and an earth move at the far corner post.
std::unique_ptr<Terrain> Rectangle(int nx = 9, int nz = 4) {
  std::vector<float> posts;
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i)
      posts.push_back(static_cast<float>(i) + 0.01f * static_cast<float>(j));
  }
  auto t = std::make_unique<Terrain>(HeightGrid(nx, nz, 10.0, std::move(posts)));
  const double sx = t->ground().size_x_m(), sz = t->ground().size_z_m();
  EXPECT_TRUE(t->SetSoil({nx - 2, nz - 2}, TriangleHalf::kUpper, Material::kRock).ok());
  EXPECT_TRUE(t->SetSoil({nx - 2, 0}, TriangleHalf::kLower, Material::kSand).ok());
  EXPECT_TRUE(t->SetSoil({0, nz - 2}, TriangleHalf::kLower, Material::kMud).ok());
  EXPECT_TRUE(t->Add({1, 1, 1}, FeatureParams::Crater(sx - 4, sz - 4, 4)).ok());
  EXPECT_TRUE(
      t->Add({1, 1, 2}, FeatureParams::Ditch({{5, sz - 3, 1, 4}, {sx / 2, sz - 3, 1, 4}}, 1.0))
          .ok());
  EXPECT_TRUE(t->Add({1, 1, 3}, FeatureParams::EarthMove({{static_cast<uint16_t>(nx - 1),
                                                           static_cast<uint16_t>(nz - 1), 250}}))
                  .ok());
  return t;
}

// `t`, loaded back, is Rectangle(nx, nz) as saved: its grid, soils (at the far corner too), blade
// work, features and digest.
void ExpectTheRectangle(const Terrain& t, const Terrain& original, int nx, int nz) {
  EXPECT_EQ(t.ground().posts_x(), nx);
  EXPECT_EQ(t.ground().posts_z(), nz);
  EXPECT_TRUE(std::ranges::equal(t.ground().posts(), original.ground().posts()));
  EXPECT_TRUE(std::ranges::equal(t.ground().soils(), original.ground().soils()));
  EXPECT_EQ(t.ground().soil({nx - 2, nz - 2}, TriangleHalf::kUpper), Material::kRock);
  EXPECT_EQ(t.BladeDeltaMm(nx - 1, nz - 1), 250);
  EXPECT_EQ(t.feature_count(), 3u);
  EXPECT_EQ(ComputeDigest(t), ComputeDigest(original));
}

TEST(TerrainFileTest, ARectangularTerrainIsVersionFourAndRoundTrips) {
  for (const auto& [nx, nz] : {std::pair{9, 4}, std::pair{4, 9}}) {
    SCOPED_TRACE(fmt::format("{} x {}", nx, nz));
    const auto original = Rectangle(nx, nz);
    const auto bytes = EncodeTerrainFile(*original);
    ByteReader header(std::span<const uint8_t>(bytes).subspan(8, 20));
    EXPECT_EQ(*header.U32(), 4u);
    // Ground section: posts_x, posts_z, spacing, posts, soils.
    const uint64_t ground_bytes = *header.U64();
    EXPECT_EQ(ground_bytes, 4u + 4 + 8 + 4u * nx * nz + 4u * (nx - 1) * (nz - 1));
    ByteReader ground(std::span<const uint8_t>(bytes).subspan(kGroundAt, ground_bytes));
    EXPECT_EQ(*ground.U32(), static_cast<uint32_t>(nx));
    EXPECT_EQ(*ground.U32(), static_cast<uint32_t>(nz));
    EXPECT_EQ(*ground.F64(), 10.0);
    // Posts row by row along x, without the blade work: post (nx - 1, 0) comes at index nx - 1.
    for (int k = 0; k < nx + 1; ++k) {
      EXPECT_EQ(*ground.F32(), k < nx ? static_cast<float>(k) : 0.01f) << k;
    }
    auto loaded = DecodeTerrainFile(bytes, "rect.dtt");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const Terrain& t = *loaded.value();
    ExpectTheRectangle(t, *original, nx, nz);
    EXPECT_EQ(t.ground().soil({0, nz - 2}, TriangleHalf::kLower), Material::kMud);
    EXPECT_EQ(EncodeTerrainFile(t), bytes);
  }
}

TEST_F(TerrainFiles, ARectangularTerrainSavesAndLoads) {
  const auto original = Rectangle();
  ASSERT_TRUE(SaveTerrain(*original, dir_ / "rect.dtt").ok());
  auto loaded = LoadTerrain(dir_ / "rect.dtt");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(ComputeDigest(*loaded.value()), ComputeDigest(*original));
  EXPECT_DOUBLE_EQ(loaded.value()->ground().size_x_m(), 80.0);
  EXPECT_DOUBLE_EQ(loaded.value()->ground().size_z_m(), 30.0);
}

// ---- Grounds past 4097 posts a side, read and written a piece at a time ----

// Wider than kMaxPostsPerSide along one side, yet 4 MB: more than one 1 MiB piece of posts and of
// soils, so features, blade work and soils at the far end cross the pieces' seams.
TEST_F(TerrainFiles, AGroundWiderThan4097PostsSavesAndLoadsBack) {
  for (const auto& [nx, nz] : {std::pair{kMaxPostsPerSide + 2, 129}, std::pair{3, 4099}}) {
    SCOPED_TRACE(fmt::format("{} x {}", nx, nz));
    const auto original = Rectangle(nx, nz);
    const fs::path path = dir_ / "wide.dtt";
    const Status saved = SaveTerrain(*original, path);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    auto loaded = LoadTerrain(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    ExpectTheRectangle(*loaded.value(), *original, nx, nz);
    // The file written a piece at a time is the file encoded whole.
    const auto whole = EncodeTerrainFile(*original);
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> on_disk((std::istreambuf_iterator<char>(in)),
                                       std::istreambuf_iterator<char>());
    EXPECT_EQ(on_disk, whole);
  }
}

// A damaged large file is refused from disk as from memory: the checksum over every piece, then
// the structure, with offsets from the start of the file.
TEST_F(TerrainFiles, ADamagedLargeFileIsRefusedWithItsOffset) {
  const int nx = kMaxPostsPerSide + 2, nz = 129;
  const auto bytes = EncodeTerrainFile(*Rectangle(nx, nz));
  ASSERT_GT(bytes.size(), 3u << 20);
  const fs::path path = dir_ / "bad.dtt";
  auto load = [&](const std::vector<uint8_t>& b) {
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    auto r = LoadTerrain(path);
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.error().message;
  };
  {
    auto b = bytes;
    b[b.size() / 2] ^= 0x40;  // a byte in the third piece
    EXPECT_NE(load(b).find(
                  fmt::format("{}: byte {}: checksum mismatch", path.string(), bytes.size() - 8)),
              std::string::npos);
  }
  {
    auto b = bytes;
    b.resize(b.size() - 1000);
    EXPECT_NE(load(b).find("byte 12: header declares a"), std::string::npos);
  }
  {
    // Post (1, 100) lies in the second piece of posts.
    auto b = bytes;
    const size_t at = kGroundAt + 16 + 4 * (static_cast<size_t>(100) * nx + 1);
    ASSERT_GT(at, kGroundAt + 16 + (1u << 20));
    PutU32(b, at, std::bit_cast<uint32_t>(std::numeric_limits<float>::quiet_NaN()));
    Reseal(b);
    EXPECT_NE(load(b).find(fmt::format("byte {}: post (1, 100) is not finite", at)),
              std::string::npos);
  }
  {
    // The last soil of the file, the far corner square's upper half, in the last piece.
    auto b = bytes;
    const size_t at = kGroundAt + 16 + 4 * static_cast<size_t>(nx) * nz +
                      2 * ((static_cast<size_t>(nz - 2) * (nx - 1) + nx - 2) * 2 + 1);
    b[at] = 0;
    b[at + 1] = 0;
    Reseal(b);
    EXPECT_NE(load(b).find(fmt::format("byte {}: soil 0 of square ({}, {}) is not a soil", at,
                                       nx - 2, nz - 2)),
              std::string::npos);
  }
  {
    // A feature record's declared length past the end of the section.
    auto b = bytes;
    const size_t features_at =
        b.size() - 8 -
        (b.size() - 8 - kGroundAt -
         (16 + 4 * static_cast<size_t>(nx) * nz + 4 * static_cast<size_t>(nx - 1) * (nz - 1)));
    PutU32(b, features_at + 4 + 8, 1u << 30);
    Reseal(b);
    EXPECT_NE(load(b).find("feature section ends inside feature 1:1:1"), std::string::npos);
  }
}

TEST(TerrainFileTest, ASquareTerrainIsStillVersionThreeAndVersionFourOfItLoads) {
  const auto square = EncodeTerrainFile(*Sample());
  EXPECT_EQ(square[8], 3);
  // The version 3 ground section: one count, then spacing, posts and soils.
  ByteReader header(std::span<const uint8_t>(square).subspan(8, 20));
  (void)header.U32();
  const uint64_t ground_bytes = *header.U64();
  EXPECT_EQ(ground_bytes, 4u + 8 + 4 * 81 + 4 * 64);
  EXPECT_EQ(square[kGroundAt], 9);
  // The same ground written as version 4 (two counts) holds the same state.
  const uint64_t feature_bytes = *header.U64();
  ByteWriter v4;
  for (size_t k = 0; k < 8; ++k) v4.U8(square[k]);
  v4.U32(4);
  v4.U64(ground_bytes + 4);
  v4.U64(feature_bytes);
  v4.U32(9);
  v4.U32(9);
  v4.Bytes(
      std::span<const uint8_t>(square).subspan(kGroundAt + 4, ground_bytes - 4 + feature_bytes));
  v4.U64(XXH3_64bits(v4.bytes().data(), v4.bytes().size()));
  auto loaded = DecodeTerrainFile(v4.bytes(), "v4.dtt");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(ComputeDigest(*loaded.value()), ComputeDigest(*Sample()));
  // Saved again, it is the version 3 file.
  EXPECT_EQ(EncodeTerrainFile(*loaded.value()), square);
}

TEST(TerrainFileTest, VersionFourGroundErrorsNameTheSide) {
  const auto bytes = EncodeTerrainFile(*Rectangle());  // 9 x 4
  {
    auto b = bytes;
    PutU32(b, kGroundAt + 4, 1);
    Reseal(b);
    ExpectRefused(b, fmt::format("byte 32: posts_z 1 is outside [2, {}]", kMaxGridPostsPerSide));
  }
  {
    auto b = bytes;
    PutU32(b, kGroundAt, kMaxGridPostsPerSide + 1);
    Reseal(b);
    ExpectRefused(b, fmt::format("byte 28: posts_x {} is outside [2, {}]", kMaxGridPostsPerSide + 1,
                                 kMaxGridPostsPerSide));
  }
  {
    // 4 x 9 posts do not fit the section of 9 x 4: the same post count, other soils.
    auto b = bytes;
    PutU32(b, kGroundAt, 4);
    PutU32(b, kGroundAt + 4, 9);
    Reseal(b);
    auto r = DecodeTerrainFile(b, "t.dtt");
    // Same section length (36 posts, 24 squares): it decodes as another ground, whose features
    // no longer fit (the crater at x 76 m is off a 30 m wide terrain).
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("was refused"), std::string::npos) << r.error().message;
  }
  {
    auto b = bytes;
    PutU32(b, kGroundAt + 4, 5);
    Reseal(b);
    ExpectRefused(b, "byte 12: ground section is 256 bytes but a 9 x 5 grid needs 324");
  }
  {
    auto b = bytes;
    const uint64_t bits = std::bit_cast<uint64_t>(0.0);
    for (size_t k = 0; k < 8; ++k) b[kGroundAt + 8 + k] = static_cast<uint8_t>(bits >> (8 * k));
    Reseal(b);
    ExpectRefused(b, "byte 36: spacing_m 0 must be finite and > 0");
  }
  {
    // Post (8, 1), the last of the second row: index 1 * 9 + 8.
    auto b = bytes;
    PutU32(b, kGroundAt + 16 + 4 * 17,
           std::bit_cast<uint32_t>(std::numeric_limits<float>::infinity()));
    Reseal(b);
    ExpectRefused(b, "post (8, 1) is not finite");
  }
  {
    // The soil of square (7, 2), the far corner square, upper half: (2 * 8 + 7) * 2 + 1.
    auto b = bytes;
    const size_t at = kGroundAt + 16 + 4 * 36 + 2 * ((2 * 8 + 7) * 2 + 1);
    b[at] = 0;
    b[at + 1] = 0;
    Reseal(b);
    ExpectRefused(b, fmt::format("byte {}: soil 0 of square (7, 2) is not a soil", at));
  }
}

}  // namespace
}  // namespace dt
