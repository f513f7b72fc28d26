#include "render/png_io.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace dt {
namespace {

// A fresh directory under the test's temporary directory, removed at the end.
class PngIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("dt_png_io_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
};

Image Pattern() {
  Image im(17, 9);
  for (int r = 0; r < im.height(); ++r) {
    for (int c = 0; c < im.width(); ++c) {
      im.set(c, r,
             {static_cast<uint8_t>(c * 15), static_cast<uint8_t>(r * 28),
              static_cast<uint8_t>((c * r) % 256), static_cast<uint8_t>(255 - c)});
    }
  }
  return im;
}

TEST_F(PngIoTest, WrittenFileDecodesToTheSamePixels) {
  const Image im = Pattern();
  ASSERT_TRUE(WritePng(im, Path("a.png")));
  const Result<Image> back = ReadPng(Path("a.png"));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back.value(), im);
}

TEST_F(PngIoTest, SamePixelsGiveTheSameBytes) {
  ASSERT_TRUE(WritePng(Pattern(), Path("a.png")));
  ASSERT_TRUE(WritePng(Pattern(), Path("b.png")));
  auto slurp = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(slurp(Path("a.png")), slurp(Path("b.png")));
}

// The bytes in memory are the file's bytes, so the two serve alike.
TEST_F(PngIoTest, EncodedInMemoryIsTheFileWritten) {
  ASSERT_TRUE(WritePng(Pattern(), Path("a.png")));
  std::ifstream in(Path("a.png"), std::ios::binary);
  const std::string file(std::istreambuf_iterator<char>(in), {});
  const Result<std::string> encoded = EncodePng(Pattern());
  ASSERT_TRUE(encoded.ok()) << encoded.error().message;
  EXPECT_EQ(encoded.value(), file);
  EXPECT_THROW((void)EncodePng(Image()), std::invalid_argument);
}

TEST_F(PngIoTest, UnwritablePathIsAnError) {
  const Status s = WritePng(Pattern(), Path("missing/dir/a.png"));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("missing/dir/a.png"), std::string::npos);
}

TEST_F(PngIoTest, MissingAndCorruptFilesAreErrors) {
  EXPECT_FALSE(ReadPng(Path("nope.png")).ok());
  {
    std::ofstream out(Path("bad.png"), std::ios::binary);
    out << "not a png at all";
  }
  EXPECT_FALSE(ReadPng(Path("bad.png")).ok());
  // A real PNG cut short.
  ASSERT_TRUE(WritePng(Pattern(), Path("full.png")));
  std::filesystem::resize_file(Path("full.png"), 60);
  EXPECT_FALSE(ReadPng(Path("full.png")).ok());
}

TEST_F(PngIoTest, EmptyImageIsMisuse) {
  EXPECT_THROW((void)WritePng(Image(), Path("e.png")), std::invalid_argument);
}

}  // namespace
}  // namespace dt
