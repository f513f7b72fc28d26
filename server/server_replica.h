// ServerReplica: the dynamic terrain server's engine: a Replica whose changes live in SQLite,
// plus terrain file export and import.
#pragma once

#include <filesystem>
#include <memory>

#include "engine/replica.h"
#include "server/sqlite_change_store.h"

namespace dt {

class ServerReplica {
 public:
  // Opens (or creates) the database, then builds the replica from every stored change.
  // config.role must be kServer or kStandby; config.store is set here. Fails if the database
  // cannot be opened or read.
  // The database records the ground's digest (terrain/base_ground.h) when it holds none; one
  // that records another ground is refused, naming both digests and where each came from
  // (config.ground_source), before any change is read. config.ground_digest, when given, must be
  // the digest of exactly this ground (ReplicaConfig); otherwise it is computed here, once, for
  // both the check and the replica.
  static Result<std::unique_ptr<ServerReplica>> Open(ReplicaConfig config, BaseGround ground,
                                                     PduBus& bus,
                                                     const std::filesystem::path& database);
  static Result<std::unique_ptr<ServerReplica>> Open(ReplicaConfig config, HeightGrid ground,
                                                     PduBus& bus,
                                                     const std::filesystem::path& database);

  Replica& replica() { return *replica_; }
  const Replica& replica() const { return *replica_; }
  SqliteChangeStore& store() { return *store_; }

  // Stores what was accepted since the last tick now (SIGTERM/SIGINT).
  Status Flush() { return replica_->Flush(); }
  // Saves the terrain as a terrain file (terrain_file.h), atomically.
  Status ExportTerrain(const std::filesystem::path& path) const;
  // Loads a terrain file and issues its features as changes of this server (Replica::Import),
  // then stores them. Refused as a whole if the file is bad or its ground differs.
  Status ImportTerrain(const std::filesystem::path& path);

 private:
  ServerReplica() = default;
  std::unique_ptr<SqliteChangeStore> store_;
  std::unique_ptr<Replica> replica_;
};

}  // namespace dt
