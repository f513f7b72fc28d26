#include "engine/prefix_hashes.h"

#include "base/demand.h"
#include "engine/change_hash.h"

namespace dt {

void PrefixHashes::Extend(const ChangeLog& log) {
  const int64_t upto = log.contiguous();
  DT_DEMAND(upto >= length());  // a gap-free point never moves back
  // No reserve to the exact length: the log grows a little between summaries, and an exact
  // reserve would copy every sum each time (quadratic); push_back's growth is amortised.
  for (int64_t s = length() + 1; s <= upto; ++s) {
    const Change* c = log.Find(s);
    DT_DEMAND(c != nullptr);  // below the gap-free point every slot is held
    prefix_.push_back(prefix_.back() + ChangeHash(*c));
  }
}

void PrefixHashes::Replace(int64_t seq, uint64_t old_hash, uint64_t new_hash) {
  if (seq < 1 || seq > length()) return;  // not hashed yet: Extend will see the new copy
  const uint64_t delta = new_hash - old_hash;
  for (size_t i = static_cast<size_t>(seq); i < prefix_.size(); ++i) prefix_[i] += delta;
}

void PrefixHashes::Truncate(int64_t upto) {
  DT_DEMAND(upto >= 0);  // a gap-free point is never negative
  if (upto < length()) prefix_.resize(static_cast<size_t>(upto) + 1);
}

}  // namespace dt
