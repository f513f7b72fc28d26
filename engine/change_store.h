// ChangeStore: where a server replica makes accepted changes durable (SQLite in server/).
#pragma once

#include <span>
#include <vector>

#include "engine/change.h"
#include "terrain/result.h"

namespace dt {

// A replica hands the store every change it accepted during one tick in one call; the store
// writes them in one transaction. A replica reports a change durable only after Append returned
// Ok, so an implementation must return only once the data survives a crash.
class ChangeStore {
 public:
  virtual ~ChangeStore() = default;
  // All or nothing: on Error nothing of the batch is stored.
  virtual Status Append(std::span<const Change> changes) = 0;
  // Every stored change, in the order stored.
  virtual Result<std::vector<Change>> LoadAll() = 0;
};

}  // namespace dt
