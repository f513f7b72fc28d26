// Tests SqliteChangeStore: round trip, restart, idempotent replay, replacing a stored change, a
// full database, files that are not its database, rows damaged or refused as PDUs, and the
// migration from schema version 1.
#include "server/sqlite_change_store.h"

#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "base/bytes.h"
#include "server/change_row.h"

namespace dt {
namespace {

namespace fs = std::filesystem;

constexpr double kTerrainSizeM = 128.0;

class SqliteChangeStoreTest : public ::testing::Test {
 protected:
  SqliteChangeStoreTest()
      : dir_(fs::temp_directory_path() /
             fmt::format("dt_sqlite_store_{}_{}", static_cast<long>(::getpid()),
                         ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~SqliteChangeStoreTest() override { fs::remove_all(dir_); }

  Result<std::unique_ptr<SqliteChangeStore>> Open(const fs::path& path) {
    return SqliteChangeStore::Open(path, kTerrainSizeM, kTerrainSizeM);
  }
  // Opens `path` and expects LoadAll to be refused with a message naming the file and `fragments`.
  void ExpectLoadRefused(const fs::path& path, const std::vector<std::string>& fragments) {
    auto store = Open(path);
    ASSERT_TRUE(store.ok()) << store.error().message;
    auto loaded = store.value()->LoadAll();
    ASSERT_FALSE(loaded.ok());
    const std::string& m = loaded.error().message;
    EXPECT_NE(m.find(path.string()), std::string::npos) << m;
    for (const auto& f : fragments)
      EXPECT_NE(m.find(f), std::string::npos) << m << "\n  lacks: " << f;
  }
  static void ExpectOpenRefused(const Result<std::unique_ptr<SqliteChangeStore>>& store,
                                const fs::path& path, const std::string& fragment) {
    ASSERT_FALSE(store.ok()) << "expected: " << fragment;
    const std::string& m = store.error().message;
    EXPECT_NE(m.find(path.string()), std::string::npos) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m << "\n  lacks: " << fragment;
  }

  fs::path dir_;
};

// Runs SQL on a database as another program would, outside the store.
class RawDatabase {
 public:
  explicit RawDatabase(const fs::path& path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
        SQLITE_OK) {
      ADD_FAILURE() << "cannot open " << path << ": " << sqlite3_errmsg(db_);
    }
  }
  ~RawDatabase() { sqlite3_close(db_); }
  RawDatabase(const RawDatabase&) = delete;
  RawDatabase& operator=(const RawDatabase&) = delete;

  void Exec(const std::string& sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      ADD_FAILURE() << sql << ": " << (err != nullptr ? err : "?");
    }
    sqlite3_free(err);
  }
  int64_t Int(const std::string& sql) {
    sqlite3_stmt* q = nullptr;
    int64_t v = -1;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &q, nullptr) == SQLITE_OK &&
        sqlite3_step(q) == SQLITE_ROW) {
      v = sqlite3_column_int64(q, 0);
    } else {
      ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
    }
    sqlite3_finalize(q);
    return v;
  }
  std::vector<uint8_t> Blob(const std::string& sql) {
    sqlite3_stmt* q = nullptr;
    std::vector<uint8_t> out;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &q, nullptr) == SQLITE_OK &&
        sqlite3_step(q) == SQLITE_ROW) {
      const auto* p = static_cast<const uint8_t*>(sqlite3_column_blob(q, 0));
      out.assign(p, p + sqlite3_column_bytes(q, 0));
    } else {
      ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
    }
    sqlite3_finalize(q);
    return out;
  }
  // Runs `sql` with one blob parameter (?1).
  void ExecWithBlob(const std::string& sql, std::span<const uint8_t> blob) {
    sqlite3_stmt* q = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &q, nullptr) != SQLITE_OK) {
      ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
      return;
    }
    sqlite3_bind_blob(q, 1, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT);
    if (sqlite3_step(q) != SQLITE_DONE) ADD_FAILURE() << sql << ": " << sqlite3_errmsg(db_);
    sqlite3_finalize(q);
  }

 private:
  sqlite3* db_ = nullptr;
};

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

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
      MakeChange(ChangeKind::kConstruct, 4, FeatureParams::Bridge(40, 60, 0.0, 6, 8, 30, 8, 3, 3)),
      MakeChange(ChangeKind::kConstruct, 5, FeatureParams::Crater(100.0, 50.0, 2)),
      // The earthworks beyond the thesis: their parameters end with a point list. Numbered past
      // the sequences the tests below add on top of these.
      MakeChange(ChangeKind::kConstruct, 600,
                 FeatureParams::Ditch({{20, 80, 2, 6}, {60, 85, 2.5, 7}, {90, 110, 2, 6}}, 1.5, 1.0,
                                      3.0, Material::kDirt)),
      MakeChange(ChangeKind::kConstruct, 601, FeatureParams::DeepCrater(70, 30, 8, 3)),
      MakeChange(ChangeKind::kConstruct, 602,
                 FeatureParams::Area({{10, 10, 0, 0}, {40, 10, 0, 0}, {25, 40, 0, 0}},
                                     Material::kWater, 2.5))};
}

TEST_F(SqliteChangeStoreTest, ChangesSurviveReopeningExactly) {
  const auto changes = Sample();
  {
    auto store = Open(dir_ / "s.db");
    ASSERT_TRUE(store.ok()) << store.error().message;
    ASSERT_TRUE(store.value()->Append(std::span(changes).first(2)).ok());
    ASSERT_TRUE(store.value()->Append(std::span(changes).subspan(2)).ok());
  }
  auto store = Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  auto loaded = store.value()->LoadAll();
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded.value(), changes);
  RawDatabase raw(dir_ / "s.db");
  EXPECT_EQ(raw.Int("PRAGMA application_id;"), kChangeDatabaseApplicationId);
  EXPECT_EQ(raw.Int("PRAGMA user_version;"), kChangeDatabaseSchemaVersion);
}

TEST_F(SqliteChangeStoreTest, CreatingLeavesNoTemporaryFileAndIgnoresAStaleOne) {
  // A start that crashed while creating the database left its half-made file.
  std::ofstream(dir_ / "s.db.creating") << "half a database";
  auto store = Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok()) << store.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "s.db.creating"));
  EXPECT_TRUE(store.value()->LoadAll().value().empty());
}

TEST_F(SqliteChangeStoreTest, AReplayedChangeIsStoredOnce) {
  const auto changes = Sample();
  auto store = Open(dir_ / "s.db");
  ASSERT_TRUE(store.ok());
  ASSERT_TRUE(store.value()->Append(changes).ok());
  ASSERT_TRUE(store.value()->Append(changes).ok());
  EXPECT_EQ(store.value()->LoadAll().value().size(), changes.size());
}

TEST_F(SqliteChangeStoreTest, ReplaceOverwritesAStoredChangeWhereAppendIgnoresIt) {
  auto changes = Sample();
  {
    auto store = Open(dir_ / "s.db");
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
  auto store = Open(dir_ / "s.db");
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
  auto store = Open(dir_ / "s.db");
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
  ExpectOpenRefused(Open(dir_ / "junk.db"), dir_ / "junk.db", "is not an SQLite database");
  EXPECT_FALSE(Open(dir_ / "no" / "such" / "dir.db").ok());
}

TEST_F(SqliteChangeStoreTest, AnEmptyFileIsRefusedNotTakenForANewDatabase) {
  std::ofstream(dir_ / "empty.db").close();
  ExpectOpenRefused(Open(dir_ / "empty.db"), dir_ / "empty.db", "is empty (0 bytes)");
  EXPECT_EQ(fs::file_size(dir_ / "empty.db"), 0u);
}

TEST_F(SqliteChangeStoreTest, ADirectoryIsRefused) {
  fs::create_directory(dir_ / "d.db");
  ExpectOpenRefused(Open(dir_ / "d.db"), dir_ / "d.db", "is a directory");
}

TEST_F(SqliteChangeStoreTest, AnotherApplicationsDatabaseIsRefusedAndLeftUntouched) {
  const fs::path path = dir_ / "notes.db";
  {
    RawDatabase raw(path);
    raw.Exec("CREATE TABLE notes (body TEXT); INSERT INTO notes VALUES ('keep me');");
  }
  const auto before = ReadBytes(path);
  const auto store = Open(path);
  ExpectOpenRefused(store, path, "another application's");
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.error().message.find("tables: notes"), std::string::npos)
      << store.error().message;
  EXPECT_EQ(ReadBytes(path), before);
  EXPECT_FALSE(fs::exists(path.string() + "-wal"));

  // A table named `changes` is not enough: the identity is the application_id.
  const fs::path other = dir_ / "other.db";
  {
    RawDatabase raw(other);
    raw.Exec("PRAGMA application_id = 1234; CREATE TABLE changes (x INTEGER);");
  }
  ExpectOpenRefused(Open(other), other, "application_id 0x000004d2");
}

TEST_F(SqliteChangeStoreTest, ASchemaVersionFromANewerBuildIsRefused) {
  ASSERT_TRUE(Open(dir_ / "s.db").ok());
  {
    RawDatabase raw(dir_ / "s.db");
    raw.Exec(fmt::format("PRAGMA user_version = {};", kChangeDatabaseSchemaVersion + 1));
  }
  ExpectOpenRefused(Open(dir_ / "s.db"), dir_ / "s.db",
                    fmt::format("schema version {}", kChangeDatabaseSchemaVersion + 1));
}

TEST_F(SqliteChangeStoreTest, AFlippedBitInAStoredCoordinateIsRefusedNamingTheRow) {
  const fs::path path = dir_ / "s.db";
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(Sample()).ok());
  }
  {
    // Change 5's crater is at x = 100.0: flip the lowest bit of its second byte.
    RawDatabase raw(path);
    std::vector<uint8_t> params = raw.Blob("SELECT params FROM changes WHERE seq = 5;");
    ByteWriter x;
    x.F64(100.0);
    const auto at = std::search(params.begin(), params.end(), x.bytes().begin(), x.bytes().end());
    ASSERT_NE(at, params.end());
    at[1] ^= 0x01;
    double flipped = 0;
    std::memcpy(&flipped, &*at, sizeof flipped);  // the format is little-endian, as is this host
    EXPECT_EQ(flipped, std::bit_cast<double>(std::bit_cast<uint64_t>(100.0) ^ 0x100));
    EXPECT_NE(flipped, 100.0);
    raw.ExecWithBlob("UPDATE changes SET params = ?1 WHERE seq = 5;", params);
  }
  ExpectLoadRefused(path, {"author 1:2 change_seq 5", "checksum mismatch"});
}

TEST_F(SqliteChangeStoreTest, AnEditedColumnIsRefusedNamingTheRow) {
  const fs::path path = dir_ / "s.db";
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(Sample()).ok());
  }
  {
    RawDatabase raw(path);
    raw.Exec("UPDATE changes SET origin_host = 3 WHERE seq = 4;");
  }
  ExpectLoadRefused(path, {"author 1:2 change_seq 4", "checksum mismatch"});
}

TEST_F(SqliteChangeStoreTest, AConstructWhoseOriginIsNotItsAuthorIsRefusedNamingTheRow) {
  // Written with a good checksum (by a faulty writer): the content checks behind it refuse it.
  const fs::path path = dir_ / "s.db";
  Change c = MakeChange(ChangeKind::kConstruct, 7, FeatureParams::Crater(50, 50, 2));
  c.id = {1, 3, 7};
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(Sample()).ok());
    ASSERT_TRUE(store.value()->Append(std::span(&c, 1)).ok());
  }
  ExpectLoadRefused(path, {"author 1:2 change_seq 7", "Construct", "only the origin creates"});
}

TEST_F(SqliteChangeStoreTest, AFeatureOffTheTerrainIsRefusedNamingTheRow) {
  const fs::path path = dir_ / "s.db";
  const Change c =
      MakeChange(ChangeKind::kUpdate, 8, FeatureParams::Crater(kTerrainSizeM + 1, 50, 2));
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(std::span(&c, 1)).ok());
  }
  ExpectLoadRefused(path, {"author 1:2 change_seq 8", "off_terrain"});
}

TEST_F(SqliteChangeStoreTest, AResealedOutOfRangeColumnIsRefusedNamingTheRow) {
  // Even with a matching checksum, a value no Change can hold is refused.
  const fs::path path = dir_ / "s.db";
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok());
    ASSERT_TRUE(store.value()->Append(Sample()).ok());
  }
  {
    ChangeRow row = ToRow(Sample()[0]);
    row.ints[static_cast<size_t>(RowColumn::kKind)] = 7;
    RawDatabase raw(path);
    raw.Exec(fmt::format("UPDATE changes SET kind = 7, checksum = {} WHERE seq = 1;",
                         static_cast<int64_t>(RowChecksum(row))));
  }
  ExpectLoadRefused(path, {"author 1:2 change_seq 1", "kind 7 is outside [0, 2]"});
}

// The schema of version 1, as the previous build wrote it.
void WriteVersion1(const fs::path& path, const std::vector<Change>& changes) {
  RawDatabase raw(path);
  raw.Exec(
      "PRAGMA journal_mode=WAL;"
      "CREATE TABLE IF NOT EXISTS changes ("
      "  author_site INTEGER NOT NULL, author_host INTEGER NOT NULL, seq INTEGER NOT NULL,"
      "  lamport INTEGER NOT NULL, kind INTEGER NOT NULL,"
      "  origin_site INTEGER NOT NULL, origin_host INTEGER NOT NULL, number INTEGER NOT NULL,"
      "  feature_type INTEGER NOT NULL, params BLOB,"
      "  PRIMARY KEY (author_site, author_host, seq));");
  for (const Change& c : changes) {
    const ChangeRow row = ToRow(c);
    std::string values;
    for (int64_t v : row.ints) values += fmt::format("{}, ", v);
    const std::string sql = fmt::format("INSERT INTO changes VALUES ({}{});", values,
                                        c.kind == ChangeKind::kDestruct ? "NULL" : "?1");
    raw.ExecWithBlob(sql, row.params);
  }
}

TEST_F(SqliteChangeStoreTest, AVersion1DatabaseIsMigratedInPlace) {
  const fs::path path = dir_ / "v1.db";
  WriteVersion1(path, Sample());
  {
    auto store = Open(path);
    ASSERT_TRUE(store.ok()) << store.error().message;
    auto loaded = store.value()->LoadAll();
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded.value(), Sample());
  }
  {
    RawDatabase raw(path);
    EXPECT_EQ(raw.Int("PRAGMA application_id;"), kChangeDatabaseApplicationId);
    EXPECT_EQ(raw.Int("PRAGMA user_version;"), kChangeDatabaseSchemaVersion);
    EXPECT_EQ(raw.Int("SELECT count(*) FROM changes WHERE checksum = 0;"), 0);
    raw.Exec("UPDATE changes SET lamport = lamport + 1 WHERE seq = 2;");
  }
  // Migrated rows are checked like any other.
  ExpectLoadRefused(path, {"author 1:2 change_seq 2", "checksum mismatch"});
}

TEST_F(SqliteChangeStoreTest, AVersion1DatabaseWithARefusedRowIsLeftAsItWas) {
  const fs::path path = dir_ / "v1.db";
  auto changes = Sample();
  changes[3].id = {1, 9, 4};  // a Construct by 1:2 of 1:9's feature
  WriteVersion1(path, changes);
  const auto store = Open(path);
  ExpectOpenRefused(store, path, "author 1:2 change_seq 4");
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.error().message.find("left as it was"), std::string::npos)
      << store.error().message;
  RawDatabase raw(path);
  EXPECT_EQ(raw.Int("PRAGMA user_version;"), 0);
  EXPECT_EQ(raw.Int("SELECT count(*) FROM pragma_table_info('changes') WHERE name = 'checksum';"),
            0);
}

}  // namespace
}  // namespace dt
