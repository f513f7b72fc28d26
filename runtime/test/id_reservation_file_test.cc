// Tests the node's feature-number reservation file: round trip, first start, and every kind of
// damage refused with the path and the problem named.
#include "runtime/id_reservation_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace dt {
namespace {

class IdReservationFileTest : public ::testing::Test {
 protected:
  IdReservationFileTest()
      : dir_(std::filesystem::temp_directory_path() /
             ("dt_ids_test_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~IdReservationFileTest() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path Path() const { return dir_ / "node-1.ids"; }
  void Write(const std::string& text) const { std::ofstream(Path(), std::ios::binary) << text; }
  std::string Read() const {
    std::ifstream in(Path(), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::string LoadError(NodeAddress a = {1, 1}) const {
    auto r = IdReservationFile(Path(), a).Load();
    return r.ok() ? "" : r.error().message;
  }

  std::filesystem::path dir_;
};

TEST_F(IdReservationFileTest, AMissingFileIsAFirstStart) {
  auto r = IdReservationFile(Path(), {1, 1}).Load();
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FALSE(r.value().has_value());
}

TEST_F(IdReservationFileTest, AReservationRoundTripsAndReplacesTheLastOne) {
  IdReservationFile f(Path(), {1, 1});
  ASSERT_TRUE(f.Reserve(256).ok());
  ASSERT_TRUE(f.Reserve(512).ok());
  auto r = IdReservationFile(Path(), {1, 1}).Load();
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value(), 512);
  EXPECT_FALSE(std::filesystem::exists(Path().string() + ".tmp"));
}

TEST_F(IdReservationFileTest, DamageIsRefusedNamingThePathAndTheProblem) {
  ASSERT_TRUE(IdReservationFile(Path(), {1, 1}).Reserve(300).ok());
  const std::string good = Read();
  // One digit changed: the checksum no longer matches.
  std::string flipped = good;
  flipped[flipped.find("300")] = '9';
  Write(flipped);
  EXPECT_NE(LoadError().find("checksum mismatch"), std::string::npos) << LoadError();
  EXPECT_NE(LoadError().find(Path().string()), std::string::npos);
  Write(good.substr(0, good.size() - 5));
  EXPECT_NE(LoadError().find("truncated"), std::string::npos) << LoadError();
  Write("");
  EXPECT_NE(LoadError().find("truncated"), std::string::npos) << LoadError();
  Write(std::string(1000, 'x'));
  EXPECT_NE(LoadError().find("more than"), std::string::npos) << LoadError();
  Write(good);
  EXPECT_NE(LoadError({1, 2}).find("written for node 1:1"), std::string::npos) << LoadError({1, 2});
  EXPECT_EQ(LoadError(), "");
}

TEST_F(IdReservationFileTest, ANonRegularFileIsRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo(Path().c_str(), 0600), 0);
  // O_NONBLOCK: returns at once although no writer exists.
  EXPECT_NE(LoadError().find("not a regular file"), std::string::npos) << LoadError();
  std::filesystem::remove(Path());
  std::filesystem::create_directory(Path());
  EXPECT_NE(LoadError().find("not a regular file"), std::string::npos) << LoadError();
}

TEST_F(IdReservationFileTest, AnUnwritableDirectoryIsAnError) {
  IdReservationFile f(dir_ / "missing" / "node-1.ids", {1, 1});
  auto s = f.Reserve(10);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("missing"), std::string::npos) << s.error().message;
}

}  // namespace
}  // namespace dt
