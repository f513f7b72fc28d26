// MemoryChangeStore: a ChangeStore in memory, for simulations that outlive a replica object.
#pragma once

#include <vector>

#include "engine/change_store.h"

namespace dt {

// Survives the destruction of the replica that used it, as a database file would survive a
// crashed process. fail_appends makes Append fail (a full disk) until cleared.
class MemoryChangeStore final : public ChangeStore {
 public:
  Status Append(std::span<const Change> changes) override;
  Result<std::vector<Change>> LoadAll() override { return changes_; }

  void set_fail_appends(bool fail) { fail_appends_ = fail; }
  size_t size() const { return changes_.size(); }
  uint64_t batches() const { return batches_; }

 private:
  std::vector<Change> changes_;
  bool fail_appends_ = false;
  uint64_t batches_ = 0;
};

}  // namespace dt
