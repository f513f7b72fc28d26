// SqliteChangeStore: the server's durable ChangeStore, one SQLite database file in WAL mode.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "engine/change_store.h"

struct sqlite3;
struct sqlite3_stmt;

namespace dt {

// The database's identity (PRAGMA application_id, "DTCS") and schema version (PRAGMA
// user_version). Version 1 had no checksum column and left both pragmas 0.
inline constexpr int32_t kChangeDatabaseApplicationId = 0x44544353;
inline constexpr int32_t kChangeDatabaseSchemaVersion = 2;

// journal_mode=WAL, synchronous=FULL: a batch is on disk when Append returns Ok, and a crash at
// any moment leaves the database holding whole batches only (SQLite's own recovery, no journal of
// ours). A change already stored (same author and sequence) is ignored by Append, so a replay is
// harmless; Replace overwrites it (an anti-entropy repair, docs/protocol.md).
// Each row carries a checksum of its content (change_row.h); LoadAll checks it and checks the
// change as a received PDU would be checked, so a damaged row stops the start instead of leaving
// this replica's digest different from every node's.
class SqliteChangeStore final : public ChangeStore {
 public:
  // Creates the database if no file is at `path` (atomically: a crash never leaves a half-made
  // file there), else opens it. Refuses, naming the path and what is wrong: a file that is not a
  // regular file, is empty, is not SQLite, is another application's SQLite database (its
  // application_id), has another schema version, or is read-only. A version 1 database is
  // migrated in place, in one transaction, after every row passed FromRow's checks.
  // The exercise's terrain is terrain_size_x_m x terrain_size_z_m: stored positions must lie on it.
  static Result<std::unique_ptr<SqliteChangeStore>> Open(const std::filesystem::path& path,
                                                         double terrain_size_x_m,
                                                         double terrain_size_z_m);
  ~SqliteChangeStore() override;
  SqliteChangeStore(const SqliteChangeStore&) = delete;
  SqliteChangeStore& operator=(const SqliteChangeStore&) = delete;

  // Does not validate: the replica hands it only changes it validated.
  Status Append(std::span<const Change> changes) override;
  Status Replace(std::span<const Change> changes) override;
  // Fails at the first row whose checksum or content is refused, naming the file, the row
  // (author site:host, change_seq, rowid) and what is wrong.
  Result<std::vector<Change>> LoadAll() override;

  // The ground the exercise's changes were made on (docs/node.md "Starting from a saved
  // terrain"): its digest (hex) and where it came from. In a table of its own beside `changes`
  // (added without a schema version: a build that does not know it reads the database as before).
  struct Ground {
    std::string digest;
    std::string source;
  };
  // The ground recorded; nullopt when none is (a new database, or one from before grounds were
  // recorded).
  Result<std::optional<Ground>> LoadGround();
  // Records the ground, replacing any recorded before.
  Status SaveGround(const Ground& ground);

  // Caps the database at this many pages (SQLite's max_page_count), as a quota or a full disk
  // would; Append then fails with SQLITE_FULL and stores nothing of the batch.
  Status LimitPages(int64_t max_pages);
  const std::filesystem::path& path() const { return path_; }

 private:
  SqliteChangeStore(std::filesystem::path path, sqlite3* db, double terrain_size_x_m,
                    double terrain_size_z_m);
  Status Exec(const char* sql);
  Status Prepare();
  Status MigrateFromVersion1();
  // One transaction of `statement` (insert_ or replace_) over the changes.
  Status Write(sqlite3_stmt* statement, std::span<const Change> changes);

  std::filesystem::path path_;
  sqlite3* db_ = nullptr;
  double terrain_size_x_m_;
  double terrain_size_z_m_;
  sqlite3_stmt* insert_ = nullptr;
  sqlite3_stmt* replace_ = nullptr;
};

}  // namespace dt
