// ChangeStore: where a server replica makes accepted changes durable (SQLite in server/).
#pragma once

#include <span>
#include <vector>

#include "base/result.h"
#include "engine/change.h"

namespace dt {

// A replica hands the store every change it accepted during one tick in one call; the store
// writes them in one transaction. A replica reports a change durable only after Append returned
// Ok, so an implementation must return only once the data survives a crash.
class ChangeStore {
 public:
  virtual ~ChangeStore() = default;
  // All or nothing: on Error nothing of the batch is stored. A change whose (author,
  // change_seq) is already stored is ignored (a replay), whatever its content.
  virtual Status Append(std::span<const Change> changes) = 0;
  // Stores each change in place of the one stored with its (author, change_seq), or as a new one
  // if there is none: anti-entropy repaired that slot (docs/protocol.md, "Anti-entropy"). All or
  // nothing, durable on Ok, like Append.
  virtual Status Replace(std::span<const Change> changes) = 0;
  // Every stored change, in the order stored.
  virtual Result<std::vector<Change>> LoadAll() = 0;
};

}  // namespace dt
