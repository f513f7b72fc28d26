// The repair rule: which of two different copies of one log slot every replica keeps.
#pragma once

#include <optional>
#include <span>

#include "base/feature_id.h"
#include "engine/change.h"
#include "pdu/pdu_type.h"

namespace dt {

// A live replica that holds a slot, as one replica sees the exercise.
struct SlotHolder {
  NodeAddress address;
  NodeRole role = NodeRole::kNode;
};

// The replica whose copy of a slot of `author`'s log every replica keeps, among the live ones
// holding it: a server (what it acknowledged), else a standby (what it stored), else the author
// itself; the lowest address among two of one role. nullopt when none of them holds the slot:
// then the lower copy wins (LowerCopy). The authority keeps its copy and everyone else takes it,
// so a slot settles on one copy without two replicas trading theirs back and forth.
std::optional<NodeAddress> SlotAuthority(NodeAddress author, std::span<const SlotHolder> holders);

// Where no authority holds the slot: true when copy `a` wins over copy `b`, by the lower XXH3-64
// of the canonical bytes (engine/change_hash.h), then the lower bytes. Of two different copies
// exactly one wins, whichever replica compares them.
bool LowerCopy(const Change& a, const Change& b);

}  // namespace dt
