#include "server/server_replica.h"

#include <stdexcept>

#include <fmt/format.h>

#include "terrain/terrain_file.h"

namespace dt {

Result<std::unique_ptr<ServerReplica>> ServerReplica::Open(ReplicaConfig config, HeightGrid ground,
                                                           PduBus& bus,
                                                           const std::filesystem::path& database) {
  return Open(std::move(config), BaseGround{std::move(ground), {}}, bus, database);
}

Result<std::unique_ptr<ServerReplica>> ServerReplica::Open(ReplicaConfig config, BaseGround ground,
                                                           PduBus& bus,
                                                           const std::filesystem::path& database) {
  if (config.role == NodeRole::kNode) {
    throw std::invalid_argument(
        fmt::format("server {}: role must be server or standby", config.address.ToString()));
  }
  auto store = SqliteChangeStore::Open(database, ground.grid.size_x_m(), ground.grid.size_z_m());
  if (!store) return store.error();
  // The digest checked against the database is the replica's too: given to it, the ground is
  // hashed once at the start instead of once here and once in the replica.
  if (!config.ground_digest) config.ground_digest = ComputeDigest(ground);
  const SqliteChangeStore::Ground mine{config.ground_digest->ToHex(), config.ground_source};
  auto recorded = store.value()->LoadGround();
  if (!recorded) return recorded.error();
  if (!recorded.value()) {
    if (auto s = store.value()->SaveGround(mine); !s) return s.error();
  } else if (recorded.value()->digest != mine.digest) {
    return Error{fmt::format(
        "{}: holds an exercise on ground {} ({}), but this server loaded ground {} ({}): refusing "
        "to start on another ground (start on that ground, or move the database away for a new "
        "exercise)",
        database.string(), recorded.value()->digest, recorded.value()->source, mine.digest,
        mine.source)};
  }
  std::unique_ptr<ServerReplica> server(new ServerReplica());
  server->store_ = std::move(store).value();
  config.store = server->store_.get();
  server->replica_ = std::make_unique<Replica>(config, std::move(ground), bus);
  if (!server->replica_->load_status()) return server->replica_->load_status().error();
  return server;
}

Status ServerReplica::ExportTerrain(const std::filesystem::path& path) const {
  return SaveTerrain(replica_->terrain(), path);
}

Status ServerReplica::ImportTerrain(const std::filesystem::path& path) {
  auto terrain = LoadTerrain(path);
  if (!terrain) return terrain.error();
  if (auto s = replica_->Import(*terrain.value()); !s) {
    return Error{fmt::format("{}: {}", path.string(), s.error().message)};
  }
  return replica_->Flush();
}

}  // namespace dt
