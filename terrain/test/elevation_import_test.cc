#include "terrain/elevation_import.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace dt {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class ImportFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "dt_import_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path Write(const std::string& name, const std::string& content) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  fs::path dir_;
};

const char* const kGoodAsc =
    "ncols 3\n"
    "nrows 3\n"
    "xllcorner 1000.5\n"
    "yllcorner -20\n"
    "cellsize 30\n"
    "NODATA_value -9999\n"
    "7 8 9\n"
    "4 5 6\n"
    "1 2 3.25\n";

void ExpectFails(const Result<HeightGrid>& r, const std::string& fragment) {
  ASSERT_FALSE(r.ok()) << "expected an error containing '" << fragment << "'";
  EXPECT_NE(r.error().message.find(fragment), std::string::npos)
      << "message: " << r.error().message << "\nexpected fragment: " << fragment;
}

TEST_F(ImportFiles, AscNorthRowComesFirst) {
  const auto r = ImportAsc(Write("good.asc", kGoodAsc));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const HeightGrid& g = r.value();
  EXPECT_EQ(g.posts_x(), 3);
  EXPECT_EQ(g.posts_z(), 3);
  EXPECT_EQ(g.spacing_m(), 30.0);
  // Row 1 of the file is the northernmost: j = 2.
  EXPECT_EQ(g.post(0, 2), 7.0f);
  EXPECT_EQ(g.post(2, 2), 9.0f);
  EXPECT_EQ(g.post(1, 1), 5.0f);
  EXPECT_EQ(g.post(0, 0), 1.0f);
  EXPECT_EQ(g.post(2, 0), 3.25f);
  EXPECT_EQ(g.soil({1, 1}, TriangleHalf::kLower), Material::kGrass);
}

TEST(AscTest, AcceptsCrlfUpperCaseKeysCentresAnyOrderAndNoNodata) {
  const auto r = ParseAsc(
      "CELLSIZE 2.5\r\nNROWS 2\r\nNCOLS 2\r\nXLLCENTER 0\r\nYLLCENTER 0\r\n\r\n"
      "-1.5e1 +2\r\n  3\t4  \r\n\r\n",
      "mem", Material::kDirt);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().spacing_m(), 2.5);
  EXPECT_EQ(r.value().post(0, 1), -15.0f);
  EXPECT_EQ(r.value().post(1, 1), 2.0f);
  EXPECT_EQ(r.value().post(0, 0), 3.0f);
  EXPECT_EQ(r.value().post(1, 0), 4.0f);
  EXPECT_EQ(r.value().soil({0, 0}, TriangleHalf::kUpper), Material::kDirt);
}

std::string WithHeader(const std::string& header, const std::string& data) { return header + data; }

const std::string kHeader3 = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n";

TEST_F(ImportFiles, MalformedAscFilesNameTheLine) {
  struct Case {
    std::string text;
    std::string fragment;
  };
  const std::vector<Case> cases = {
      {"nrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n7 8 9\n",
       "line 5: header has no ncols"},
      {"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\n1 2 3\n", "line 5: header has no cellsize"},
      {"ncols 3\nnrows 3\nyllcorner 0\ncellsize 1\n1 2 3\n", "line 5: header has no xllcorner"},
      {"ncols 3\nnrows 3\nfoo 1\n", "line 3: unknown header key 'foo'"},
      {"ncols 3\nncols 3\n", "line 2: ncols given twice"},
      {"ncols 3\nnrows 3\nxllcorner 0\nxllcenter 0\n", "line 4: xllcenter given twice"},
      {"ncols 3.0\n", "line 1: ncols = '3.0' is not an integer"},
      {"ncols\n", "line 1: header line 'ncols' must be a key and one value"},
      {"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize abc\n",
       "line 5: cellsize = 'abc' is not a finite number"},
      {"ncols 3\nnrows 4\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n",
       "line 6: ncols = 3 and nrows = 4 differ"},
      {"ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n",
       "line 6: ncols = 1 is outside [2, 4097]"},
      {"ncols 4098\nnrows 4098\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n",
       "line 6: ncols = 4098 is outside [2, 4097]"},  // kMaxPostsPerSide
      {"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 0\n1 2 3\n4 5 6\n7 8 9\n",
       "line 6: cellsize = 0 must be > 0"},
      {"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize -2\n1 2 3\n4 5 6\n7 8 9\n",
       "line 6: cellsize = -2 must be > 0"},
      {"ncols 3\nnrows 3\nxllcorner nan\nyllcorner 0\ncellsize 1\n",
       "line 3: xllcorner = 'nan' is not a finite number"},
      {WithHeader(kHeader3, "1 2 3\n4 5\n7 8 9\n"),
       "line 7: row 2 has 2 values, expected ncols = 3"},
      {WithHeader(kHeader3, "1 2 3\n4 5 6 6\n7 8 9\n"), "line 7: row 2 has 4 values"},
      {WithHeader(kHeader3, "1 2 3\n4 x 6\n7 8 9\n"), "line 7: column 2: 'x' is not a finite"},
      {WithHeader(kHeader3, "1 2 3\n4 5 6\n7 8 inf\n"), "line 8: column 3: 'inf' is not a finite"},
      {WithHeader(kHeader3, "1 2 3\n4 5 6\n7 8 1e39\n"), "line 8: column 3: 1e39 does not fit"},
      {WithHeader(kHeader3, "1 2 3\n4 5 6\n7 8 9\n1 1 1\n"), "line 9: data after the last of 3"},
      {WithHeader(kHeader3, "1 2 3\n4 5 6\n\n"), "file ends after 2 of 3 rows"},
      {"ncols 100\nnrows 100\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
       "line 6: header declares 100 x 100 cells but the file has only 59 bytes"},
      {WithHeader(kHeader3, ""), "line 5: file ends after 0 of 3 rows"},
      {"ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n"
       "1 2 3\n4 -9999 6\n7 8 9\n",
       "line 8: column 2: NODATA value -9999 (cells without data are refused)"},
      {"", "header has no ncols"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    ExpectFails(ParseAsc(c.text, "t.asc"), "t.asc: ");
    ExpectFails(ParseAsc(c.text, "t.asc"), c.fragment);
    const fs::path path = Write("bad.asc", c.text);
    ExpectFails(ImportAsc(path), path.string() + ": ");
    ExpectFails(ImportAsc(path), c.fragment);
  }
}

TEST(AscTest, BadSoilThrows) {
  EXPECT_THROW((void)ParseAsc(kGoodAsc, "mem", Material::kFromGround), std::invalid_argument);
  EXPECT_THROW((void)ParseAsc(kGoodAsc, "mem", static_cast<Material>(99)), std::invalid_argument);
}

TEST_F(ImportFiles, MissingFileIsAnError) {
  ExpectFails(ImportAsc(dir_ / "absent.asc"), "absent.asc: cannot open");
  ExpectFails(ImportPgm(dir_ / "absent.pgm"), "absent.pgm: cannot open");
}

// A P5 image with the given header text and raw samples.
std::string Pgm(const std::string& header, const std::vector<uint8_t>& raster) {
  return header + std::string(raster.begin(), raster.end());
}

std::vector<uint8_t> Bytes(const std::string& s) { return {s.begin(), s.end()}; }

TEST_F(ImportFiles, Pgm16BitIsBigEndianAndScaled) {
  // 2 x 2, maxval 65535, a comment in the header. Rows: north first.
  const std::string file =
      Pgm("P5\n# made by hand\n2 2\n65535\n", {0x00, 0x01, 0x01, 0x00, 0xFF, 0xFF, 0x12, 0x34});
  PgmImportOptions options;
  options.spacing_m = 4.0;
  options.metres_per_level = 0.5;
  options.base_elevation_m = -10.0;
  options.soil = Material::kRock;
  const auto r = ImportPgm(Write("h.pgm", file), options);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const HeightGrid& g = r.value();
  EXPECT_EQ(g.spacing_m(), 4.0);
  EXPECT_EQ(g.post(0, 1), static_cast<float>(-10.0 + 1 * 0.5));
  EXPECT_EQ(g.post(1, 1), static_cast<float>(-10.0 + 256 * 0.5));
  EXPECT_EQ(g.post(0, 0), static_cast<float>(-10.0 + 65535 * 0.5));
  EXPECT_EQ(g.post(1, 0), static_cast<float>(-10.0 + 0x1234 * 0.5));
  EXPECT_EQ(g.soil({0, 0}, TriangleHalf::kLower), Material::kRock);
}

TEST(PgmTest, EightBitUsesOneBytePerSampleAndDefaultScale) {
  const auto r = ParsePgm(Bytes(Pgm("P5 2 2 255 ", {10, 20, 30, 255})), "mem");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const PgmImportOptions defaults;
  EXPECT_EQ(r.value().spacing_m(), defaults.spacing_m);
  EXPECT_EQ(r.value().post(0, 1), static_cast<float>(10 * defaults.metres_per_level));
  EXPECT_EQ(r.value().post(1, 0), static_cast<float>(255 * defaults.metres_per_level));
}

TEST_F(ImportFiles, MalformedPgmFilesNameTheByteOffset) {
  struct Case {
    std::string file;
    std::string fragment;
  };
  const std::vector<Case> cases = {
      {"", "byte 0: not a binary PGM"},
      {"P6 2 2 255 ", "byte 0: not a binary PGM"},
      {"P2 2 2 255 1 2 3 4", "byte 0: plain (ASCII) PGM 'P2' is not supported"},
      {"P52 2 255 ", "byte 2: expected whitespace before the width"},
      {"P5 x 2 255 ", "byte 3: expected the width (a decimal number), found byte 0x78"},
      {"P5 2", "byte 4: expected whitespace before the height"},
      {"P5 2 ", "byte 5: file ends before the height"},
      {"P5 2 2 # comment to the end", "byte 27: file ends before the maxval"},
      {"P5 2 3 255 ", "byte 4: width 2 and height 3 differ"},
      {"P5 1 1 255 ", "byte 2: width 1 is outside [2, 4097]"},
      {"P5 4098 4098 255 ", "byte 2: width 4098 is outside [2, 4097]"},
      {"P5 99999999 99999999 255 ", "byte 3: width is too large"},
      {"P5 2 2 0 ", "byte 6: maxval 0 is outside [1, 65535]"},
      {"P5 2 2 65536 ", "byte 6: maxval 65536 is outside [1, 65535]"},
      {"P5 2 2 255", "byte 10: expected one whitespace byte after maxval"},
      {Pgm("P5 2 2 255 ", {1, 2, 3}),
       "byte 14: file is truncated: the 2 x 2 raster needs 4 bytes "
       "from byte 11, only 3 present"},
      {Pgm("P5 2 2 1000 ", {0, 1, 0, 2, 0, 3, 0}),
       "byte 19: file is truncated: the 2 x 2 raster needs 8 bytes from byte 12, only 7 present"},
      {Pgm("P5 2 2 255 ", {1, 2, 3, 4, 5}), "byte 15: 1 unexpected bytes after the raster"},
      {Pgm("P5 2 2 100 ", {1, 2, 101, 4}), "byte 13: sample 101 exceeds maxval 100"},
      {Pgm("P5 2 2 1000 ", {0, 1, 0, 2, 0x03, 0xE9, 0, 4}), "byte 16: sample 1001 exceeds maxval"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    ExpectFails(ParsePgm(Bytes(c.file), "t.pgm"), "t.pgm: " + c.fragment);
    const fs::path path = Write("bad.pgm", c.file);
    ExpectFails(ImportPgm(path), path.string() + ": " + c.fragment);
  }
}

TEST(PgmTest, ElevationsBeyondFloatAreRefused) {
  PgmImportOptions options;
  options.metres_per_level = 1e38;
  ExpectFails(ParsePgm(Bytes(Pgm("P5 2 2 255 ", {1, 2, 200, 4})), "t.pgm", options),
              "byte 13: sample 200 gives elevation");
}

TEST(PgmTest, BadOptionsThrow) {
  const auto file = Bytes(Pgm("P5 2 2 255 ", {1, 2, 3, 4}));
  for (auto tweak : std::vector<void (*)(PgmImportOptions&)>{
           [](PgmImportOptions& o) { o.spacing_m = 0.0; },
           [](PgmImportOptions& o) { o.spacing_m = std::numeric_limits<double>::infinity(); },
           [](PgmImportOptions& o) { o.metres_per_level = -1.0; },
           [](PgmImportOptions& o) { o.metres_per_level = std::nan(""); },
           [](PgmImportOptions& o) { o.base_elevation_m = std::nan(""); },
           [](PgmImportOptions& o) { o.soil = Material::kFromGround; }}) {
    PgmImportOptions o;
    tweak(o);
    EXPECT_THROW((void)ParsePgm(file, "mem", o), std::invalid_argument);
  }
}

}  // namespace
}  // namespace dt
