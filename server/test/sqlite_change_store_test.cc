// Tests SqliteChangeStore: round trip, restart, idempotent replay, replacing a stored change, a
// full database and bad files.
#include "server/sqlite_change_store.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace dt {
namespace {

class SqliteChangeStoreTest : public ::testing::Test {
 protected:
  SqliteChangeStoreTest()
      : dir_(std::filesystem::temp_directory_path() /
             fmt::format("dt_sqlite_store_{}_{}", static_cast<long>(::getpid()),
                         ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~SqliteChangeStoreTest() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

Change MakeChange(ChangeKind kind, uint32_t seq, FeatureParams params) {
  Change c;
  c.kind = kind;
  c.id = {1, 2, seq};
  c.params = std::move(params);
  c.stamp.changed_by = {1, 2};
  c.stamp.change_seq = seq;
  c.stamp.lamport = 100 + seq;
  return c;
}

std::vector<Change> Sample() {
  auto crater = FeatureParams::Crater(10.5, 20.25, 3);
  crater.vertex_edits = {{1, 2, 0.5}, {3, 1, -0.25}};
  FeatureParams gone;
  gone.type = FeatureType::kBerm;
  return {
      MakeChange(ChangeKind::kConstruct, 1, crater),
      MakeChange(ChangeKind::kUpdate, 2, FeatureParams::Berm(30, 30, 0.7, 20, 4, 2)),
      MakeChange(ChangeKind::kDestruct, 3, gone),
      MakeChange(ChangeKind::kConstruct, 4, FeatureParams::Bridge(40, 60, 0.0, 6, 8, 30, 8, 3, 3))};
}

TEST_F(SqliteChangeStoreTest, ChangesSurviveReopeningExactly) {
  const auto changes = Sample();
  {
    auto store = SqliteChangeStore::Open(dir_ / "s.db");
    ASSERT_TRUE(store.ok()) << store.error().message;
    ASSERT_TRUE(store.value()->Append(std::span(changes).first(2)).ok());
    ASSERT_TRUE(store.value()->Append(std::span(changes).subspan(2)).ok());
  }
  auto store = SqliteChangeStore::Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  auto loaded = store.value()->LoadAll();
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded.value(), changes);
}

TEST_F(SqliteChangeStoreTest, AReplayedChangeIsStoredOnce) {
  const auto changes = Sample();
  auto store = SqliteChangeStore::Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  ASSERT_TRUE(store.value()->Append(changes).ok());
  ASSERT_TRUE(store.value()->Append(changes).ok());
  EXPECT_EQ(store.value()->LoadAll().value().size(), changes.size());
}

TEST_F(SqliteChangeStoreTest, ReplaceOverwritesAStoredChangeWhereAppendIgnoresIt) {
  auto changes = Sample();
  {
    auto store = SqliteChangeStore::Open(dir_ / "s.db");
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(changes).ok());
    Change other = changes[1];
    other.params = FeatureParams::Berm(35, 30, 0.2, 25, 4, 2);
    other.stamp.lamport = 999;
    ASSERT_TRUE(store.value()->Append(std::span(&other, 1)).ok());  // a replay: ignored
    EXPECT_EQ(store.value()->LoadAll().value(), changes);
    // An anti-entropy repair of slot 2, and a slot not stored yet.
    const Change fresh = MakeChange(ChangeKind::kConstruct, 9, FeatureParams::Crater(5, 5, 1));
    const std::vector<Change> repaired = {other, fresh};
    ASSERT_TRUE(store.value()->Replace(repaired).ok());
    changes[1] = other;
    changes.push_back(fresh);
  }
  auto store = SqliteChangeStore::Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  auto loaded = store.value()->LoadAll();
  ASSERT_TRUE(loaded.ok());
  ASSERT_EQ(loaded.value().size(), changes.size());
  for (const Change& c : changes) {
    EXPECT_NE(std::find(loaded.value().begin(), loaded.value().end(), c), loaded.value().end())
        << c.stamp.change_seq;
  }
}

TEST_F(SqliteChangeStoreTest, AFullDatabaseRefusesTheWholeBatch) {
  auto store = SqliteChangeStore::Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  ASSERT_TRUE(store.value()->Append(Sample()).ok());
  ASSERT_TRUE(store.value()->LimitPages(1).ok());  // fewer pages than the database has
  std::vector<Change> big;
  for (uint32_t i = 10; i < 500; ++i) {
    big.push_back(MakeChange(ChangeKind::kConstruct, i, FeatureParams::Crater(10, 10, 2)));
  }
  const Status s = store.value()->Append(big);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("full"), std::string::npos) << s.error().message;
  EXPECT_EQ(store.value()->LoadAll().value().size(), Sample().size());
}

TEST_F(SqliteChangeStoreTest, AFileThatIsNotADatabaseIsRefused) {
  {
    std::ofstream f(dir_ / "junk.db");
    f << "this is not an SQLite database, just text that is long enough to have a header";
  }
  auto store = SqliteChangeStore::Open(dir_ / "junk.db");
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.error().message.find("junk.db"), std::string::npos) << store.error().message;
  auto missing_dir = SqliteChangeStore::Open(dir_ / "no" / "such" / "dir.db");
  EXPECT_FALSE(missing_dir.ok());
}

}  // namespace
}  // namespace dt
