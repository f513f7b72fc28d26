// PrefixHashes: sums of change hashes over the prefixes 1..s of one author's log, for anti-entropy.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/change_log.h"

namespace dt {

// prefix(s) = ChangeHash(1) + ... + ChangeHash(s) modulo 2^64, for s up to the log's gap-free
// point: 8 bytes per change, and the hash of any range lo..hi is prefix(hi) - prefix(lo - 1), so
// a summary or a bucket costs O(1). A sum does not depend on the order the changes arrived in,
// and each change is hashed once, when the gap-free point first passes it.
class PrefixHashes {
 public:
  // Hashes the changes from length() + 1 up to the log's gap-free point.
  void Extend(const ChangeLog& log);
  // The sequences covered: 1..length().
  int64_t length() const { return static_cast<int64_t>(prefix_.size()) - 1; }
  // Sum over 1..s; 0 <= s <= length().
  uint64_t At(int64_t s) const { return prefix_[static_cast<size_t>(s)]; }
  // Sum over lo..hi; 1 <= lo <= hi + 1, hi <= length().
  uint64_t Range(int64_t lo, int64_t hi) const { return At(hi) - At(lo - 1); }
  // The change in slot `seq` was replaced: its hash went from old_hash to new_hash.
  void Replace(int64_t seq, uint64_t old_hash, uint64_t new_hash);
  // The log's gap-free point fell to `upto` (a held change was removed): sums beyond it go, and
  // Extend hashes again whatever fills those slots. Nothing changes if upto >= length().
  void Truncate(int64_t upto);

 private:
  std::vector<uint64_t> prefix_{0};
};

}  // namespace dt
