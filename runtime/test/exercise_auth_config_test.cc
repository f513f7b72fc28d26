// The exercise file's [auth] table: key files, keyless exercises, and the shipped exercises'
// choice.
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include "runtime/exercise_config.h"
#include "runtime/test/exercise_config_samples.h"

namespace dt {
namespace {

using test::kGood;
using test::Replace;

// A directory with an exercise file and, beside it in keys/, key files of chosen lengths.
class AuthConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("dt-excfg-auth-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "keys");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  void WriteKey(const std::string& name, size_t n) {
    std::ofstream out(dir_ / "keys" / name, std::ios::binary);
    for (size_t i = 0; i < n; ++i) out.put(static_cast<char>(i));
  }
  // kGood with its [auth] table replaced by `auth` (empty: none at all), loaded from dir_.
  ExerciseConfig Load(const std::string& auth) {
    { std::ofstream(dir_ / "e.toml") << Replace(kGood, "[auth]\nmode = \"none\"\n", auth); }
    return LoadExerciseConfig(dir_ / "e.toml");
  }
  std::string ErrorOfLoad(const std::string& auth) {
    try {
      Load(auth);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(AuthConfigTest, ReadsTheKeyFileBesideTheExerciseFile) {
  WriteKey("ex.key", 32);
  const ExerciseConfig c = Load("[auth]\nkey_file = \"keys/ex.key\"\nclock_tolerance_ms = 5000\n");
  EXPECT_FALSE(c.auth.keyless);
  EXPECT_EQ(c.auth.key_file, dir_ / "keys" / "ex.key");
  ASSERT_NE(c.auth.key, nullptr);
  EXPECT_EQ(c.auth.key->size(), 32u);
  EXPECT_EQ(c.auth.clock_tolerance_ms, 5000);
  EXPECT_EQ(Load("[auth]\nkey_file = \"keys/ex.key\"\n").auth.clock_tolerance_ms, 30000);
}

TEST_F(AuthConfigTest, AFileNamedWithoutAFolderResolvesInTheCurrentDirectory) {
  WriteKey("ex.key", 32);
  Load("[auth]\nkey_file = \"keys/ex.key\"\n");
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir_);
  std::string error;
  ExerciseConfig c;
  try {
    c = LoadExerciseConfig("e.toml");
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::filesystem::current_path(cwd);
  ASSERT_EQ(error, "");
  EXPECT_EQ(c.auth.key_file, dir_ / "keys" / "ex.key");
  EXPECT_EQ(c.nodes[0].scenario, dir_ / "scen/a.toml");
}

TEST_F(AuthConfigTest, KeylessIsAnExplicitChoice) {
  const ExerciseConfig c = Load("[auth]\nmode = \"none\"\n");
  EXPECT_TRUE(c.auth.keyless);
  EXPECT_EQ(c.auth.key, nullptr);
  std::string e = ErrorOfLoad("");
  EXPECT_NE(e.find("e.toml: auth: missing"), std::string::npos) << e;
  EXPECT_NE(e.find("mode = \"none\""), std::string::npos) << e;
  EXPECT_NE(e.find("key_file"), std::string::npos) << e;
  e = ErrorOfLoad("[auth]\n");
  EXPECT_NE(e.find("auth.key_file: missing"), std::string::npos) << e;
  WriteKey("ex.key", 32);
  e = ErrorOfLoad("[auth]\nmode = \"none\"\nkey_file = \"keys/ex.key\"\n");
  EXPECT_NE(e.find("auth.key_file: mode = \"none\" runs without a key"), std::string::npos) << e;
  e = ErrorOfLoad("[auth]\nmode = \"off\"\n");
  EXPECT_NE(e.find("auth.mode"), std::string::npos) << e;
  EXPECT_NE(e.find("off"), std::string::npos) << e;
  e = ErrorOfLoad("[auth]\nmode = \"none\"\nclock_tolerance_ms = 0\n");
  EXPECT_NE(e.find("auth.clock_tolerance_ms"), std::string::npos) << e;
  e = ErrorOfLoad("[auth]\nmode = \"none\"\nkeyfile = \"x\"\n");
  EXPECT_NE(e.find("auth.keyfile: unknown key"), std::string::npos) << e;
}

TEST_F(AuthConfigTest, AMissingKeyFileNamesItsPath) {
  const std::string e = ErrorOfLoad("[auth]\nkey_file = \"keys/absent.key\"\n");
  EXPECT_NE(e.find("auth.key_file"), std::string::npos) << e;
  EXPECT_NE(e.find((dir_ / "keys" / "absent.key").string()), std::string::npos) << e;
}

TEST_F(AuthConfigTest, AShortKeyNamesItsPathAndLength) {
  WriteKey("short.key", 16);
  const std::string e = ErrorOfLoad("[auth]\nkey_file = \"keys/short.key\"\n");
  EXPECT_NE(e.find("auth.key_file"), std::string::npos) << e;
  EXPECT_NE(e.find((dir_ / "keys" / "short.key").string()), std::string::npos) << e;
  EXPECT_NE(e.find("holds 16 bytes"), std::string::npos) << e;
}

TEST_F(AuthConfigTest, AnUnreadableKeyFileIsAnError) {
  WriteKey("locked.key", 32);
  std::filesystem::permissions(dir_ / "keys" / "locked.key", std::filesystem::perms::none);
  if (std::ifstream(dir_ / "keys" / "locked.key").good()) {
    GTEST_SKIP() << "running as root: permissions do not stop reads";
  }
  const std::string e = ErrorOfLoad("[auth]\nkey_file = \"keys/locked.key\"\n");
  EXPECT_NE(e.find((dir_ / "keys" / "locked.key").string()), std::string::npos) << e;
  EXPECT_NE(e.find("Permission denied"), std::string::npos) << e;
}

// Every exercise the repository ships (the demo's and the drills') is authenticated with a key
// that exists, or says it is keyless.
TEST(ExerciseConfigTest, ShippedExercisesChooseTheirAuthentication) {
  int keyed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(
           std::filesystem::path(DT_SOURCE_DIR) / "configs/exercises")) {
    if (entry.path().extension() != ".toml") continue;
    const ExerciseConfig c = LoadExerciseConfig(entry.path());
    if (!c.auth.keyless) {
      EXPECT_NE(c.auth.key, nullptr) << entry.path();
      ++keyed;
    }
  }
  EXPECT_GE(keyed, 3);
}

}  // namespace
}  // namespace dt
