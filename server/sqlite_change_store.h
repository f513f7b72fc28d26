// SqliteChangeStore: the server's durable ChangeStore, one SQLite database file in WAL mode.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

#include "engine/change_store.h"

struct sqlite3;
struct sqlite3_stmt;

namespace dt {

// journal_mode=WAL, synchronous=FULL: a batch is on disk when Append returns Ok, and a crash at
// any moment leaves the database holding whole batches only (SQLite's own recovery, no journal of
// ours). A change already stored (same author and sequence) is ignored by Append, so a replay is
// harmless; Replace overwrites it (an anti-entropy repair, docs/protocol.md).
class SqliteChangeStore final : public ChangeStore {
 public:
  // Opens or creates the database. Fails (naming the path and SQLite's message) if the file
  // cannot be opened or is not a dynterrain change database.
  static Result<std::unique_ptr<SqliteChangeStore>> Open(const std::filesystem::path& path);
  ~SqliteChangeStore() override;
  SqliteChangeStore(const SqliteChangeStore&) = delete;
  SqliteChangeStore& operator=(const SqliteChangeStore&) = delete;

  Status Append(std::span<const Change> changes) override;
  Status Replace(std::span<const Change> changes) override;
  Result<std::vector<Change>> LoadAll() override;

  // Caps the database at this many pages (SQLite's max_page_count), as a quota or a full disk
  // would; Append then fails with SQLITE_FULL and stores nothing of the batch.
  Status LimitPages(int64_t max_pages);
  const std::filesystem::path& path() const { return path_; }

 private:
  SqliteChangeStore(std::filesystem::path path, sqlite3* db);
  Status Exec(const char* sql);
  Status Prepare();
  // One transaction of `statement` (insert_ or replace_) over the changes.
  Status Write(sqlite3_stmt* statement, std::span<const Change> changes);

  std::filesystem::path path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  sqlite3_stmt* replace_ = nullptr;
};

}  // namespace dt
