// MemoryChangeStore: a ChangeStore in memory, for simulations that outlive a replica object.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "engine/change_store.h"

namespace dt {

// Survives the destruction of the replica that used it, as a database file would survive a
// crashed process. fail_appends makes Append and Replace fail (a full disk) until cleared.
class MemoryChangeStore final : public ChangeStore {
 public:
  Status Append(std::span<const Change> changes) override;
  Status Replace(std::span<const Change> changes) override;
  Result<std::vector<Change>> LoadAll() override { return changes_; }
  // The stored change of (author, seq); null if none. Mutable: a test corrupts a stored change.
  Change* Find(NodeAddress author, int64_t seq);

  void set_fail_appends(bool fail) { fail_appends_ = fail; }
  size_t size() const { return changes_.size(); }
  uint64_t batches() const { return batches_; }

 private:
  std::vector<Change> changes_;
  std::map<std::pair<NodeAddress, int64_t>, size_t> index_;  // (author, seq) -> changes_ index
  bool fail_appends_ = false;
  uint64_t batches_ = 0;
};

}  // namespace dt
