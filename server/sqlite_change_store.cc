#include "server/sqlite_change_store.h"

#include <sqlite3.h>

#include <fmt/format.h>

#include "terrain/bytes.h"

namespace dt {
namespace {

constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS changes ("
    "  author_site INTEGER NOT NULL, author_host INTEGER NOT NULL, seq INTEGER NOT NULL,"
    "  lamport INTEGER NOT NULL, kind INTEGER NOT NULL,"
    "  origin_site INTEGER NOT NULL, origin_host INTEGER NOT NULL, number INTEGER NOT NULL,"
    "  feature_type INTEGER NOT NULL, params BLOB,"
    "  PRIMARY KEY (author_site, author_host, seq));";

std::string SqlError(sqlite3* db) { return db != nullptr ? sqlite3_errmsg(db) : "out of memory"; }

}  // namespace

Result<std::unique_ptr<SqliteChangeStore>> SqliteChangeStore::Open(
    const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  const int rc =
      sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  if (rc != SQLITE_OK) {
    std::string msg = SqlError(db);
    sqlite3_close(db);
    return Error{fmt::format("{}: cannot open the change database: {}", path.string(), msg)};
  }
  std::unique_ptr<SqliteChangeStore> store(new SqliteChangeStore(path, db));
  for (const char* sql : {"PRAGMA journal_mode=WAL;", "PRAGMA synchronous=FULL;", kSchema}) {
    if (auto s = store->Exec(sql); !s) return s.error();
  }
  if (auto s = store->Prepare(); !s) return s.error();
  return store;
}

SqliteChangeStore::SqliteChangeStore(std::filesystem::path path, sqlite3* db)
    : path_(std::move(path)), db_(db) {}

SqliteChangeStore::~SqliteChangeStore() {
  sqlite3_finalize(insert_);
  sqlite3_finalize(replace_);
  sqlite3_close(db_);
}

Status SqliteChangeStore::Exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err != nullptr ? err : SqlError(db_);
    sqlite3_free(err);
    return Error{fmt::format("{}: {} failed: {}", path_.string(), sql, msg)};
  }
  return Status::Ok();
}

Status SqliteChangeStore::Prepare() {
  constexpr const char* kColumns =
      " INTO changes (author_site, author_host, seq, lamport, kind, origin_site,"
      " origin_host, number, feature_type, params) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?);";
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
    sqlite3_reset(statement);
    sqlite3_clear_bindings(statement);
    sqlite3_bind_int(statement, 1, c.stamp.changed_by.site);
    sqlite3_bind_int(statement, 2, c.stamp.changed_by.host);
    sqlite3_bind_int64(statement, 3, c.stamp.change_seq);
    sqlite3_bind_int64(statement, 4, static_cast<sqlite3_int64>(c.stamp.lamport));
    sqlite3_bind_int(statement, 5, static_cast<int>(c.kind));
    sqlite3_bind_int(statement, 6, c.id.site);
    sqlite3_bind_int(statement, 7, c.id.host);
    sqlite3_bind_int64(statement, 8, c.id.number);
    sqlite3_bind_int(statement, 9, static_cast<int>(c.params.type));
    ByteWriter w;
    if (c.kind != ChangeKind::kDestruct) {
      EncodeFeatureParams(c.params, w);
      sqlite3_bind_blob(statement, 10, w.bytes().data(), static_cast<int>(w.bytes().size()),
                        SQLITE_TRANSIENT);
    } else {
      sqlite3_bind_null(statement, 10);
    }
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
  const char* sql =
      "SELECT author_site, author_host, seq, lamport, kind, origin_site, origin_host, number,"
      " feature_type, params FROM changes ORDER BY rowid;";
  if (sqlite3_prepare_v2(db_, sql, -1, &q, nullptr) != SQLITE_OK) {
    return Error{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))};
  }
  std::vector<Change> out;
  int rc;
  while ((rc = sqlite3_step(q)) == SQLITE_ROW) {
    Change c;
    c.stamp.changed_by = {static_cast<uint16_t>(sqlite3_column_int(q, 0)),
                          static_cast<uint16_t>(sqlite3_column_int(q, 1))};
    c.stamp.change_seq = static_cast<uint32_t>(sqlite3_column_int64(q, 2));
    c.stamp.lamport = static_cast<uint64_t>(sqlite3_column_int64(q, 3));
    const int kind = sqlite3_column_int(q, 4);
    c.id = {static_cast<uint16_t>(sqlite3_column_int(q, 5)),
            static_cast<uint16_t>(sqlite3_column_int(q, 6)),
            static_cast<uint32_t>(sqlite3_column_int64(q, 7))};
    const int type = sqlite3_column_int(q, 8);
    const std::string where = fmt::format("{}: change {}:{}", path_.string(),
                                          c.stamp.changed_by.ToString(), c.stamp.change_seq);
    if (kind < 0 || kind > 2 || !IsValidFeatureType(static_cast<uint16_t>(type)) ||
        c.stamp.change_seq == 0 || c.id.number == 0) {
      sqlite3_finalize(q);
      return Error{fmt::format("{} is malformed (kind {}, type {})", where, kind, type)};
    }
    c.kind = static_cast<ChangeKind>(kind);
    c.params.type = static_cast<FeatureType>(type);
    if (c.kind != ChangeKind::kDestruct) {
      const auto* blob = static_cast<const uint8_t*>(sqlite3_column_blob(q, 9));
      const int n = sqlite3_column_bytes(q, 9);
      ByteReader r(std::span<const uint8_t>(blob, static_cast<size_t>(n)));
      auto p = DecodeFeatureParams(r);
      if (!p) {
        sqlite3_finalize(q);
        return Error{fmt::format("{}: bad parameters: {}", where, p.error().message)};
      }
      c.params = std::move(p).value();
    }
    out.push_back(std::move(c));
  }
  sqlite3_finalize(q);
  if (rc != SQLITE_DONE) {
    return Error{fmt::format("{}: reading changes failed: {}", path_.string(), SqlError(db_))};
  }
  return out;
}

}  // namespace dt
