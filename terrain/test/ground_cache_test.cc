#include "terrain/ground_cache.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "terrain/random_terrain.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

// A rectangular random ground with a few soils set, so posts and soils both count.
HeightGrid Ground() {
  HeightGrid g = MakeRandomTerrain({.posts_x = 301, .posts_z = 203, .spacing_m = 5.0, .seed = 7});
  g.set_soil({3, 4}, TriangleHalf::kUpper, Material::kRock);
  g.set_soil({299, 201}, TriangleHalf::kLower, Material::kMud);
  return g;
}

class GroundCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("ground_cache_test." + std::to_string(getpid()) + "." +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Opens the cache for kKey, counting the builds.
  GroundCacheOpened Open() {
    return OpenGroundCache(dir_, kKey, [this] {
      ++builds_;
      return Ground();
    });
  }

  static constexpr const char* kKey = "test ground 301 x 203 seed 7";
  std::filesystem::path dir_;
  int builds_ = 0;
};

TEST_F(GroundCacheTest, BuildsOnceThenMapsTheSameGroundWithTheSameDigest) {
  const HeightGrid in_memory = Ground();
  GroundCacheOpened first = Open();
  EXPECT_TRUE(first.built);
  EXPECT_EQ(first.build_reason, "absent");
  EXPECT_EQ(first.file, GroundCacheFile(dir_, kKey));
  EXPECT_TRUE(first.grid.is_mapped());
  GroundCacheOpened second = Open();
  EXPECT_FALSE(second.built);
  EXPECT_EQ(builds_, 1);
  for (const HeightGrid* g : {&first.grid, &second.grid}) {
    EXPECT_EQ(g->posts_x(), 301);
    EXPECT_EQ(g->posts_z(), 203);
    EXPECT_EQ(g->spacing_m(), 5.0);
    EXPECT_TRUE(std::ranges::equal(g->posts(), in_memory.posts()));
    EXPECT_TRUE(std::ranges::equal(g->soils(), in_memory.soils()));
    EXPECT_EQ(ComputeDigest(*g), ComputeDigest(in_memory));
    EXPECT_EQ(g->ElevationAt(123.4, 567.8), in_memory.ElevationAt(123.4, 567.8));
  }
  // Another key names another file.
  EXPECT_NE(GroundCacheFile(dir_, "another"), first.file);
}

TEST_F(GroundCacheTest, ADamagedFileIsRebuiltNeverTrusted) {
  const std::filesystem::path file = Open().file;
  const auto size = std::filesystem::file_size(file);
  const TerrainDigest good = ComputeDigest(Ground());
  struct Damage {
    const char* name;
    void (*apply)(const std::filesystem::path&, uintmax_t);
    const char* reason_part;
  };
  const Damage damages[] = {
      {"truncated",
       [](const std::filesystem::path& f, uintmax_t n) {
         std::filesystem::resize_file(f, n - 1000);
       },
       "not the"},
      {"one post's byte flipped",
       [](const std::filesystem::path& f, uintmax_t) {
         std::fstream s(f, std::ios::in | std::ios::out | std::ios::binary);
         s.seekp(kGroundCacheHeaderBytes + 4 * 1000 + 1);
         s.put('\x5a');
       },
       "hash"},
      {"header overwritten",
       [](const std::filesystem::path& f, uintmax_t) {
         std::fstream s(f, std::ios::in | std::ios::out | std::ios::binary);
         s.write("NOTGROUND", 9);
       },
       "not a ground cache file"},
      {"header only",
       [](const std::filesystem::path& f, uintmax_t) { std::filesystem::resize_file(f, 100); },
       "shorter than its header"},
  };
  for (const Damage& d : damages) {
    SCOPED_TRACE(d.name);
    d.apply(file, size);
    const int before = builds_;
    GroundCacheOpened again = Open();
    EXPECT_TRUE(again.built);
    EXPECT_EQ(builds_, before + 1);
    EXPECT_NE(again.build_reason.find(d.reason_part), std::string::npos) << again.build_reason;
    EXPECT_EQ(ComputeDigest(again.grid), good);
    EXPECT_EQ(std::filesystem::file_size(file), size);
  }
}

TEST_F(GroundCacheTest, EditsStayInTheGridThatMadeThem) {
  GroundCacheOpened a = Open();
  GroundCacheOpened b = Open();
  const float before = b.grid.post(10, 20);
  a.grid.set_post(10, 20, before + 7.0f);
  a.grid.set_soil({5, 5}, TriangleHalf::kLower, Material::kSand);
  EXPECT_EQ(a.grid.post(10, 20), before + 7.0f);
  EXPECT_EQ(b.grid.post(10, 20), before);
  EXPECT_EQ(b.grid.soil({5, 5}, TriangleHalf::kLower), Ground().soil({5, 5}, TriangleHalf::kLower));
  // A copy of the edited grid keeps the edit; the file does not take it.
  const HeightGrid copy = a.grid;
  EXPECT_EQ(copy.post(10, 20), before + 7.0f);
  EXPECT_EQ(copy.soil({5, 5}, TriangleHalf::kLower), Material::kSand);
  EXPECT_EQ(ComputeDigest(copy), ComputeDigest(a.grid));
  EXPECT_EQ(ComputeDigest(Open().grid), ComputeDigest(Ground()));
  EXPECT_EQ(builds_, 1);
}

TEST_F(GroundCacheTest, ATerrainOnTheMappedGroundIsTheTerrainOnTheGroundInMemory) {
  Terrain mapped(Open().grid);
  Terrain in_memory(Ground());
  for (Terrain* t : {&mapped, &in_memory}) {
    ASSERT_TRUE(t->Add({1, 1, 1}, FeatureParams::Crater(400.0, 300.0, 8.0)).ok());
    ASSERT_TRUE(t->Add({1, 1, 2}, FeatureParams::EarthMove({{40, 30, 250}, {41, 30, -120}})).ok());
    ASSERT_TRUE(t->SetPostElevation(100, 100, 3.5f).ok());
  }
  EXPECT_EQ(ComputeDigest(mapped), ComputeDigest(in_memory));
  EXPECT_EQ(mapped.ElevationAt(401.0, 299.0), in_memory.ElevationAt(401.0, 299.0));
  // The file is still the bare ground.
  EXPECT_EQ(ComputeDigest(Open().grid), ComputeDigest(Ground()));
}

TEST_F(GroundCacheTest, ProcessesStartingAtOnceBuildItOnce) {
  constexpr int kProcesses = 4;
  std::vector<pid_t> children;
  for (int k = 0; k < kProcesses; ++k) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      int status = 3;
      try {
        GroundCacheOpened o = Open();
        status = ComputeDigest(o.grid) == ComputeDigest(Ground()) ? (o.built ? 1 : 0) : 2;
      } catch (...) {
      }
      _exit(status);
    }
    children.push_back(pid);
  }
  int built = 0;
  for (pid_t pid : children) {
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_LE(WEXITSTATUS(status), 1) << "a process saw a wrong ground or failed";
    built += WEXITSTATUS(status);
  }
  EXPECT_EQ(built, 1);
  // No temporary file is left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

// Sets the file's last use (its modification time) `days` ago.
void UsedDaysAgo(const std::filesystem::path& file, int days) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const int64_t s = std::chrono::duration_cast<std::chrono::seconds>(now).count() - days * 86400;
  const timespec times[2] = {{s, 0}, {s, 0}};
  ASSERT_EQ(utimensat(AT_FDCWD, file.c_str(), times, 0), 0) << file;
}

bool Mentions(const std::vector<std::string>& removed, const std::filesystem::path& file) {
  return std::ranges::any_of(
      removed, [&](const std::string& r) { return r.starts_with(file.string() + " ("); });
}

TEST_F(GroundCacheTest, ABuildRemovesFilesUnusedTooLongThenTheOldestOverTheBudget) {
  auto build = [&](const std::string& key, GroundCachePruning pruning) {
    return OpenGroundCache(
        dir_, key, [] { return HeightGrid(33, 1.0); }, pruning);
  };
  constexpr GroundCachePruning kRoomy{.max_age_days = 30, .budget_bytes = uint64_t{1} << 40};
  const std::filesystem::path a = build("a", kRoomy).file, b = build("b", kRoomy).file,
                              c = build("c", kRoomy).file, held = build("held", kRoomy).file;
  const auto bytes = std::filesystem::file_size(a);
  const std::filesystem::path temp = dir_ / "ground-0123.dtg.tmp.99999";
  const std::filesystem::path other = dir_ / "notes.txt";
  std::ofstream(temp) << "a build that died";
  std::ofstream(other) << "not a cache file";
  UsedDaysAgo(a, 40);
  UsedDaysAgo(b, 40);
  UsedDaysAgo(held, 40);
  UsedDaysAgo(temp, 40);
  UsedDaysAgo(other, 40);
  UsedDaysAgo(c, 10);
  // b is opened again: that is a use, and it stays.
  EXPECT_FALSE(build("b", kRoomy).built);
  // Another process is rebuilding `held`: it holds the file's lock, and the file stays.
  const int lock = open((held.string() + ".lock").c_str(), O_RDWR | O_CLOEXEC);
  ASSERT_GE(lock, 0);
  ASSERT_EQ(flock(lock, LOCK_EX | LOCK_NB), 0);
  const GroundCacheOpened d = build("d", kRoomy);
  close(lock);
  EXPECT_TRUE(d.built);
  EXPECT_EQ(d.removed.size(), 2u) << ::testing::PrintToString(d.removed);
  EXPECT_TRUE(Mentions(d.removed, a)) << ::testing::PrintToString(d.removed);
  EXPECT_TRUE(Mentions(d.removed, temp));
  EXPECT_FALSE(std::filesystem::exists(a));
  EXPECT_FALSE(std::filesystem::exists(a.string() + ".lock"));
  EXPECT_FALSE(std::filesystem::exists(temp));
  for (const auto& kept : {b, c, held, other, d.file}) {
    EXPECT_TRUE(std::filesystem::exists(kept)) << kept;
  }
  // Over a budget of three files: the oldest in use go first (held, then c), the new one stays.
  UsedDaysAgo(held, 20);
  UsedDaysAgo(c, 10);
  UsedDaysAgo(b, 5);
  UsedDaysAgo(d.file, 1);
  const GroundCacheOpened e =
      build("e", {.max_age_days = 30, .budget_bytes = 3 * bytes + bytes / 2});
  EXPECT_EQ(e.removed.size(), 2u) << ::testing::PrintToString(e.removed);
  EXPECT_TRUE(Mentions(e.removed, held));
  EXPECT_TRUE(Mentions(e.removed, c));
  for (const auto& kept : {b, d.file, e.file, other}) {
    EXPECT_TRUE(std::filesystem::exists(kept)) << kept;
  }
  // Opening without building never removes anything.
  UsedDaysAgo(b, 400);
  EXPECT_TRUE(build("e", {.max_age_days = 1, .budget_bytes = 0}).removed.empty());
  EXPECT_TRUE(std::filesystem::exists(b));
}

}  // namespace
}  // namespace dt
