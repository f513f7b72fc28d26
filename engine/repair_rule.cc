#include "engine/repair_rule.h"

#include "engine/change_hash.h"

namespace dt {

std::optional<NodeAddress> SlotAuthority(NodeAddress author, std::span<const SlotHolder> holders) {
  for (NodeRole role : {NodeRole::kServer, NodeRole::kStandby}) {
    std::optional<NodeAddress> best;
    for (const SlotHolder& h : holders) {
      if (h.role == role && (!best || h.address < *best)) best = h.address;
    }
    if (best) return best;
  }
  for (const SlotHolder& h : holders) {
    if (h.address == author) return author;
  }
  return std::nullopt;
}

bool LowerCopy(const Change& a, const Change& b) {
  const uint64_t ha = ChangeHash(a);
  const uint64_t hb = ChangeHash(b);
  if (ha != hb) return ha < hb;
  return CanonicalChangeBytes(a) < CanonicalChangeBytes(b);
}

}  // namespace dt
