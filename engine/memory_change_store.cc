#include "engine/memory_change_store.h"

#include <fmt/format.h>

namespace dt {

Status MemoryChangeStore::Append(std::span<const Change> changes) {
  if (fail_appends_) {
    return Error{fmt::format("memory store refuses a batch of {} changes (failure injected)",
                             changes.size())};
  }
  for (const Change& c : changes) {
    // A replay is ignored, as SQLite's INSERT OR IGNORE does.
    if (index_.emplace(std::pair{c.author(), int64_t{c.stamp.change_seq}}, changes_.size())
            .second) {
      changes_.push_back(c);
    }
  }
  ++batches_;
  return Status::Ok();
}

Status MemoryChangeStore::Replace(std::span<const Change> changes) {
  if (fail_appends_) {
    return Error{fmt::format("memory store refuses to replace {} changes (failure injected)",
                             changes.size())};
  }
  for (const Change& c : changes) {
    auto [it, fresh] =
        index_.emplace(std::pair{c.author(), int64_t{c.stamp.change_seq}}, changes_.size());
    if (fresh) {
      changes_.push_back(c);
    } else {
      changes_[it->second] = c;
    }
  }
  ++batches_;
  return Status::Ok();
}

Change* MemoryChangeStore::Find(NodeAddress author, int64_t seq) {
  auto it = index_.find({author, seq});
  return it == index_.end() ? nullptr : &changes_[it->second];
}

}  // namespace dt
