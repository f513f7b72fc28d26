#include "server/sqlite_change_store.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "base/regular_file.h"
#include "log/log.h"
#include "server/change_row.h"

namespace dt {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCreateTable =
    "CREATE TABLE changes ("
    "  author_site INTEGER NOT NULL, author_host INTEGER NOT NULL, seq INTEGER NOT NULL,"
    "  lamport INTEGER NOT NULL, kind INTEGER NOT NULL,"
    "  origin_site INTEGER NOT NULL, origin_host INTEGER NOT NULL, number INTEGER NOT NULL,"
    "  feature_type INTEGER NOT NULL, params BLOB, checksum INTEGER NOT NULL,"
    "  PRIMARY KEY (author_site, author_host, seq));";

// Version 1's columns: version 2 added `checksum`.
const std::vector<std::string> kVersion1Columns = {
    "author_site", "author_host", "seq",    "lamport",      "kind",
    "origin_site", "origin_host", "number", "feature_type", "params"};

// Every SQLite database starts with these 16 bytes.
constexpr std::array<char, 16> kSqliteMagic = {'S', 'Q', 'L', 'i', 't', 'e', ' ', 'f',
                                               'o', 'r', 'm', 'a', 't', ' ', '3', '\0'};

// The columns LoadAll and the migration read: rowid, the integer columns, params, checksum.
constexpr const char* kSelectRows =
    "SELECT rowid, author_site, author_host, seq, lamport, kind, origin_site, origin_host, number,"
    " feature_type, params, checksum FROM changes ORDER BY rowid;";
// These numbers are also the INSERT's 1-based parameters (which have no rowid before them).
constexpr int kParamsColumn = 1 + static_cast<int>(kRowIntegerColumns);
constexpr int kChecksumColumn = kParamsColumn + 1;

std::string SqlError(sqlite3* db) { return db != nullptr ? sqlite3_errmsg(db) : "out of memory"; }

// Closes a connection that Open has not yet handed to a store.
struct Connection {
  sqlite3* db = nullptr;
  Connection() = default;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection() { sqlite3_close(db); }
  sqlite3* release() { return std::exchange(db, nullptr); }
};

Status ExecOn(sqlite3* db, const fs::path& path, const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err != nullptr ? err : SqlError(db);
    sqlite3_free(err);
    return Error{fmt::format("{}: {} failed: {}", path.string(), sql, msg)};
  }
  return Status::Ok();
}

// The first column of every row of `sql`, as text.
Result<std::vector<std::string>> Column(sqlite3* db, const fs::path& path, const char* sql) {
  sqlite3_stmt* q = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &q, nullptr) != SQLITE_OK) {
    return Error{fmt::format("{}: cannot read the database: {}", path.string(), SqlError(db))};
  }
  std::vector<std::string> out;
  int rc;
  while ((rc = sqlite3_step(q)) == SQLITE_ROW) {
    const auto* text = sqlite3_column_text(q, 0);
    out.emplace_back(text != nullptr ? reinterpret_cast<const char*>(text) : "");
  }
  sqlite3_finalize(q);
  if (rc != SQLITE_DONE) {
    return Error{fmt::format("{}: cannot read the database: {}", path.string(), SqlError(db))};
  }
  return out;
}

Result<int64_t> Pragma(sqlite3* db, const fs::path& path, const char* name) {
  const std::string sql = fmt::format("PRAGMA {};", name);
  sqlite3_stmt* q = nullptr;
  int64_t value = 0;
  const bool ok = sqlite3_prepare_v2(db, sql.c_str(), -1, &q, nullptr) == SQLITE_OK &&
                  sqlite3_step(q) == SQLITE_ROW;
  if (ok) value = sqlite3_column_int64(q, 0);
  sqlite3_finalize(q);
  if (!ok) {
    return Error{fmt::format("{}: cannot read the database: {}", path.string(), SqlError(db))};
  }
  return value;
}

Status SyncDirectory(const fs::path& dir, const fs::path& path) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    return Error{fmt::format("{}: created, but opening {} to fsync it failed: {}", path.string(),
                             dir.string(), std::strerror(errno))};
  }
  const int synced = ::fsync(fd);
  const int saved = errno;
  ::close(fd);
  if (synced != 0) {
    return Error{fmt::format("{}: created, but fsync of {} failed: {}", path.string(), dir.string(),
                             std::strerror(saved))};
  }
  return Status::Ok();
}

// Builds an empty database beside `path` and links it into place, so `path` never names a
// half-made database: an empty file there is refused by Open, and a crash during the first start
// must not produce one. link() fails if `path` appeared meanwhile, where rename would replace it.
Status CreateDatabase(const fs::path& path) {
  const std::string temp = path.string() + ".creating";
  std::error_code ec;
  fs::remove(temp, ec);  // left by a start that crashed while creating
  fs::remove(temp + "-journal", ec);
  {
    Connection c;
    if (sqlite3_open_v2(temp.c_str(), &c.db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
        SQLITE_OK) {
      return Error{
          fmt::format("{}: cannot create the change database: {}", path.string(), SqlError(c.db))};
    }
    const std::string schema = fmt::format(
        "PRAGMA synchronous=FULL; BEGIN; {} PRAGMA application_id={}; PRAGMA user_version={}; "
        "COMMIT;",
        kCreateTable, kChangeDatabaseApplicationId, kChangeDatabaseSchemaVersion);
    if (auto s = ExecOn(c.db, temp, schema.c_str()); !s) {
      fs::remove(temp, ec);
      return s;
    }
  }
  if (::link(temp.c_str(), path.c_str()) != 0) {
    const int saved = errno;
    fs::remove(temp, ec);
    return Error{fmt::format("{}: cannot create the change database: link from {} failed: {}",
                             path.string(), temp, std::strerror(saved))};
  }
  fs::remove(temp, ec);
  return SyncDirectory(path.has_parent_path() ? path.parent_path() : fs::path("."), path);
}

// The file checks SQLite does not make: it would take an empty file for an empty database.
Status CheckDatabaseFile(const fs::path& path, const struct stat& st) {
  if (!S_ISREG(st.st_mode)) {
    return Error{fmt::format("{}: is {}, not a change database file", path.string(),
                             FileTypeName(st.st_mode))};
  }
  if (st.st_size == 0) {
    return Error{fmt::format(
        "{}: is empty (0 bytes), not a dynterrain change database (a truncated copy?); restore "
        "it, or remove it to start with no stored changes",
        path.string())};
  }
  std::array<char, kSqliteMagic.size()> head{};
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Error{fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno))};
  const ssize_t n = ::read(fd, head.data(), head.size());
  ::close(fd);
  if (n != static_cast<ssize_t>(head.size()) || head != kSqliteMagic) {
    return Error{
        fmt::format("{}: is not an SQLite database (it does not start with the SQLite "
                    "header), so not a dynterrain change database",
                    path.string())};
  }
  return Status::Ok();
}

// A row's columns as stored; an error if a column holds a value of the wrong type.
Result<ChangeRow> ReadRow(sqlite3_stmt* q, std::string& where, const fs::path& path) {
  ChangeRow row;
  const char* wrong = nullptr;
  for (size_t i = 0; i < kRowIntegerColumns; ++i) {
    const int col = 1 + static_cast<int>(i);
    row.ints[i] = sqlite3_column_int64(q, col);
    if (wrong == nullptr && sqlite3_column_type(q, col) != SQLITE_INTEGER) {
      wrong = kRowColumnNames[i];
    }
  }
  const int params_type = sqlite3_column_type(q, kParamsColumn);
  if (params_type == SQLITE_BLOB) {
    const auto* blob = static_cast<const uint8_t*>(sqlite3_column_blob(q, kParamsColumn));
    row.params.assign(blob, blob + sqlite3_column_bytes(q, kParamsColumn));
  } else if (wrong == nullptr && params_type != SQLITE_NULL) {
    wrong = "params";
  }
  where =
      fmt::format("{}: row {} (rowid {})", path.string(), RowName(row), sqlite3_column_int64(q, 0));
  if (wrong != nullptr) {
    return Error{fmt::format("{}: column {} does not hold a value of its type", where, wrong)};
  }
  return row;
}

}  // namespace

Result<std::unique_ptr<SqliteChangeStore>> SqliteChangeStore::Open(const fs::path& path,
                                                                   double terrain_size_x_m,
                                                                   double terrain_size_z_m) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) {
      return Error{fmt::format("{}: cannot examine: {}", path.string(), std::strerror(errno))};
    }
    if (auto s = CreateDatabase(path); !s) return s.error();
    if (::stat(path.c_str(), &st) != 0) {
      return Error{fmt::format("{}: cannot examine: {}", path.string(), std::strerror(errno))};
    }
  }
  if (auto s = CheckDatabaseFile(path, st); !s) return s.error();

  Connection c;
  if (sqlite3_open_v2(path.c_str(), &c.db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    return Error{
        fmt::format("{}: cannot open the change database: {}", path.string(), SqlError(c.db))};
  }
  auto application_id = Pragma(c.db, path, "application_id");
  if (!application_id) return application_id.error();
  auto version = Pragma(c.db, path, "user_version");
  if (!version) return version.error();
  bool migrate = false;
  if (application_id.value() == kChangeDatabaseApplicationId) {
    if (version.value() != kChangeDatabaseSchemaVersion) {
      return Error{
          fmt::format("{}: is a dynterrain change database of schema version {}; this "
                      "build reads version {} (and migrates version 1)",
                      path.string(), version.value(), kChangeDatabaseSchemaVersion)};
    }
  } else {
    auto tables =
        Column(c.db, path, "SELECT name FROM sqlite_schema WHERE type = 'table' ORDER BY name;");
    if (!tables) return tables.error();
    auto columns = Column(c.db, path, "SELECT name FROM pragma_table_info('changes');");
    if (!columns) return columns.error();
    migrate = application_id.value() == 0 && version.value() == 0 &&
              tables.value() == std::vector<std::string>{"changes"} &&
              columns.value() == kVersion1Columns;
    if (!migrate) {
      return Error{fmt::format(
          "{}: is an SQLite database, but another application's, not a dynterrain change "
          "database (application_id {:#010x} where dynterrain's is {:#010x}; user_version {}; "
          "tables: {}); move it away or point run_dir elsewhere",
          path.string(), static_cast<uint32_t>(application_id.value()),
          static_cast<uint32_t>(kChangeDatabaseApplicationId), version.value(),
          tables.value().empty() ? std::string("none")
                                 : fmt::format("{}", fmt::join(tables.value(), ", ")))};
    }
  }
  if (sqlite3_db_readonly(c.db, "main") == 1) {
    return Error{fmt::format("{}: is read-only; the server must be able to write its changes",
                             path.string())};
  }
  std::unique_ptr<SqliteChangeStore> store(
      new SqliteChangeStore(path, c.release(), terrain_size_x_m, terrain_size_z_m));
  for (const char* sql : {"PRAGMA journal_mode=WAL;", "PRAGMA synchronous=FULL;"}) {
    if (auto s = store->Exec(sql); !s) return s.error();
  }
  if (migrate) {
    if (auto s = store->MigrateFromVersion1(); !s) return s.error();
  }
  if (auto s = store->Prepare(); !s) return s.error();
  return store;
}

SqliteChangeStore::SqliteChangeStore(fs::path path, sqlite3* db, double terrain_size_x_m,
                                     double terrain_size_z_m)
    : path_(std::move(path)),
      db_(db),
      terrain_size_x_m_(terrain_size_x_m),
      terrain_size_z_m_(terrain_size_z_m) {}

SqliteChangeStore::~SqliteChangeStore() {
  sqlite3_finalize(insert_);
  sqlite3_finalize(replace_);
  sqlite3_close(db_);
}

Status SqliteChangeStore::Exec(const char* sql) { return ExecOn(db_, path_, sql); }

namespace {
constexpr const char* kCreateGroundTable =
    "CREATE TABLE IF NOT EXISTS ground (id INTEGER PRIMARY KEY CHECK (id = 1),"
    " digest TEXT NOT NULL, source TEXT NOT NULL);";
}  // namespace

Result<std::optional<SqliteChangeStore::Ground>> SqliteChangeStore::LoadGround() {
  if (auto s = Exec(kCreateGroundTable); !s) return s.error();
  auto digest = Column(db_, path_, "SELECT digest FROM ground WHERE id = 1;");
  if (!digest) return digest.error();
  auto source = Column(db_, path_, "SELECT source FROM ground WHERE id = 1;");
  if (!source) return source.error();
  if (digest.value().empty() || source.value().empty()) return std::optional<Ground>{};
  return std::optional<Ground>{Ground{digest.value().front(), source.value().front()}};
}

Status SqliteChangeStore::SaveGround(const Ground& ground) {
  if (auto s = Exec(kCreateGroundTable); !s) return s;
  sqlite3_stmt* q = nullptr;
  const char* sql = "INSERT OR REPLACE INTO ground (id, digest, source) VALUES (1, ?, ?);";
  bool ok = sqlite3_prepare_v2(db_, sql, -1, &q, nullptr) == SQLITE_OK;
  ok = ok && sqlite3_bind_text(q, 1, ground.digest.c_str(), -1, SQLITE_TRANSIENT) == SQLITE_OK &&
       sqlite3_bind_text(q, 2, ground.source.c_str(), -1, SQLITE_TRANSIENT) == SQLITE_OK &&
       sqlite3_step(q) == SQLITE_DONE;
  sqlite3_finalize(q);
  if (!ok) {
    return Error{
        fmt::format("{}: cannot record the exercise's ground: {}", path_.string(), SqlError(db_))};
  }
  return Status::Ok();
}

Status SqliteChangeStore::Prepare() {
  constexpr const char* kColumns =
      " INTO changes (author_site, author_host, seq, lamport, kind, origin_site,"
      " origin_host, number, feature_type, params, checksum)"
      " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?);";
  const std::string insert = std::string("INSERT OR IGNORE") + kColumns;
  const std::string replace = std::string("INSERT OR REPLACE") + kColumns;
  for (auto [sql, statement] : {std::pair{&insert, &insert_}, std::pair{&replace, &replace_}}) {
    if (sqlite3_prepare_v2(db_, sql->c_str(), -1, statement, nullptr) != SQLITE_OK) {
      return Error{
          fmt::format("{}: not a dynterrain change database: {}", path_.string(), SqlError(db_))};
    }
  }
  return Status::Ok();
}

// One transaction: the checksum column, a checksum for every row that passes FromRow, the new
// identity. Any refused row rolls it all back, leaving the version 1 file as it was.
Status SqliteChangeStore::MigrateFromVersion1() {
  if (auto s = Exec("BEGIN IMMEDIATE;"); !s) return s;
  auto fail = [&](Error e) -> Status {
    (void)Exec("ROLLBACK;");
    return Error{
        fmt::format("{}; migrating from schema version 1 was abandoned and the file left "
                    "as it was",
                    e.message)};
  };
  if (auto s = Exec("ALTER TABLE changes ADD COLUMN checksum INTEGER NOT NULL DEFAULT 0;"); !s) {
    return fail(s.error());
  }
  sqlite3_stmt* q = nullptr;
  sqlite3_stmt* set = nullptr;
  if (sqlite3_prepare_v2(db_, kSelectRows, -1, &q, nullptr) != SQLITE_OK ||
      sqlite3_prepare_v2(db_, "UPDATE changes SET checksum = ? WHERE rowid = ?;", -1, &set,
                         nullptr) != SQLITE_OK) {
    Error e{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))};
    sqlite3_finalize(q);
    sqlite3_finalize(set);
    return fail(e);
  }
  auto finish = [&](Error e) {
    sqlite3_finalize(q);
    sqlite3_finalize(set);
    return fail(std::move(e));
  };
  int64_t rows = 0;
  int rc;
  while ((rc = sqlite3_step(q)) == SQLITE_ROW) {
    std::string where;
    auto row = ReadRow(q, where, path_);
    if (!row) return finish(row.error());
    if (auto c = FromRow(row.value(), terrain_size_x_m_, terrain_size_z_m_); !c) {
      return finish(Error{fmt::format("{}: {}", where, c.error().message)});
    }
    sqlite3_reset(set);
    sqlite3_bind_int64(set, 1, static_cast<sqlite3_int64>(RowChecksum(row.value())));
    sqlite3_bind_int64(set, 2, sqlite3_column_int64(q, 0));
    if (sqlite3_step(set) != SQLITE_DONE) {
      return finish(
          Error{fmt::format("{}: writing its checksum failed: {}", where, SqlError(db_))});
    }
    ++rows;
  }
  if (rc != SQLITE_DONE) {
    return finish(
        Error{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))});
  }
  sqlite3_finalize(q);
  sqlite3_finalize(set);
  const std::string identity =
      fmt::format("PRAGMA application_id={}; PRAGMA user_version={};", kChangeDatabaseApplicationId,
                  kChangeDatabaseSchemaVersion);
  if (auto s = Exec(identity.c_str()); !s) return fail(s.error());
  if (auto s = Exec("COMMIT;"); !s) return fail(s.error());
  DT_LOG_INFO("{}: migrated {} stored changes from schema version 1 to {} (row checksums)",
              path_.string(), rows, kChangeDatabaseSchemaVersion);
  return Status::Ok();
}

Status SqliteChangeStore::LimitPages(int64_t max_pages) {
  return Exec(fmt::format("PRAGMA max_page_count={};", max_pages).c_str());
}

Status SqliteChangeStore::Append(std::span<const Change> changes) {
  return Write(insert_, changes);
}

Status SqliteChangeStore::Replace(std::span<const Change> changes) {
  return Write(replace_, changes);
}

Status SqliteChangeStore::Write(sqlite3_stmt* statement, std::span<const Change> changes) {
  if (changes.empty()) return Status::Ok();
  if (auto s = Exec("BEGIN IMMEDIATE;"); !s) return s;
  for (const Change& c : changes) {
    const ChangeRow row = ToRow(c);
    sqlite3_reset(statement);
    sqlite3_clear_bindings(statement);
    for (size_t i = 0; i < kRowIntegerColumns; ++i) {
      sqlite3_bind_int64(statement, 1 + static_cast<int>(i), row.ints[i]);
    }
    if (c.kind != ChangeKind::kDestruct) {
      sqlite3_bind_blob(statement, kParamsColumn, row.params.data(),
                        static_cast<int>(row.params.size()), SQLITE_TRANSIENT);
    } else {
      sqlite3_bind_null(statement, kParamsColumn);
    }
    sqlite3_bind_int64(statement, kChecksumColumn, static_cast<sqlite3_int64>(RowChecksum(row)));
    if (sqlite3_step(statement) != SQLITE_DONE) {
      std::string msg = SqlError(db_);
      sqlite3_reset(statement);
      (void)Exec("ROLLBACK;");
      return Error{fmt::format("{}: storing change {}:{} failed: {}", path_.string(),
                               c.stamp.changed_by.ToString(), c.stamp.change_seq, msg)};
    }
  }
  sqlite3_reset(statement);
  if (auto s = Exec("COMMIT;"); !s) {
    (void)Exec("ROLLBACK;");
    return s;
  }
  return Status::Ok();
}

Result<std::vector<Change>> SqliteChangeStore::LoadAll() {
  sqlite3_stmt* q = nullptr;
  if (sqlite3_prepare_v2(db_, kSelectRows, -1, &q, nullptr) != SQLITE_OK) {
    return Error{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))};
  }
  auto fail = [&](std::string message) -> Error {
    sqlite3_finalize(q);
    return Error{std::move(message)};
  };
  std::vector<Change> out;
  int rc;
  while ((rc = sqlite3_step(q)) == SQLITE_ROW) {
    std::string where;
    auto row = ReadRow(q, where, path_);
    if (!row) return fail(row.error().message);
    if (sqlite3_column_type(q, kChecksumColumn) != SQLITE_INTEGER) {
      return fail(fmt::format("{}: has no checksum", where));
    }
    const auto stored = static_cast<uint64_t>(sqlite3_column_int64(q, kChecksumColumn));
    const uint64_t computed = RowChecksum(row.value());
    if (stored != computed) {
      return fail(
          fmt::format("{}: checksum mismatch: stored {:016x}, computed {:016x} (the row "
                      "was changed outside dynterrain, or the file is damaged)",
                      where, stored, computed));
    }
    auto c = FromRow(row.value(), terrain_size_x_m_, terrain_size_z_m_);
    if (!c) return fail(fmt::format("{}: {}", where, c.error().message));
    out.push_back(std::move(c).value());
  }
  sqlite3_finalize(q);
  if (rc != SQLITE_DONE) {
    return Error{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))};
  }
  return out;
}

}  // namespace dt
