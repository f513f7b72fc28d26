#include "engine/memory_change_store.h"

#include <fmt/format.h>

namespace dt {

Status MemoryChangeStore::Append(std::span<const Change> changes) {
  if (fail_appends_) {
    return Error{fmt::format("memory store refuses a batch of {} changes (failure injected)",
                             changes.size())};
  }
  changes_.insert(changes_.end(), changes.begin(), changes.end());
  ++batches_;
  return Status::Ok();
}

}  // namespace dt
