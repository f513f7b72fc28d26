// IdReservationFile: a node's feature-number reservation (engine/id_reservation.h) kept in a
// small file beside its control socket, so a node killed and restarted never reissues an ID.
#pragma once

#include <filesystem>

#include "base/feature_id.h"
#include "engine/id_reservation.h"

namespace dt {

// One line, "dynterrain-ids 1 <site>:<host> <number> <checksum>", replaced atomically (written
// to a temporary file, fsynced, renamed over the old one, directory fsynced), so a crash leaves
// either the old or the new reservation, never a torn one. A missing file is a first start;
// a file that is damaged, truncated or written for another address is an Error naming the path
// and the problem: the node refuses to start rather than guess (docs/protocol.md).
class IdReservationFile final : public IdReservation {
 public:
  IdReservationFile(std::filesystem::path path, NodeAddress address);

  Result<std::optional<int64_t>> Load() override;
  Status Reserve(int64_t number) override;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  NodeAddress address_;
};

}  // namespace dt
