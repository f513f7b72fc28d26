#include "node/change_log.h"

#include <algorithm>
#include <tuple>

namespace dt {

bool ChangeLog::Insert(const Change& change) {
  const int64_t seq = change.stamp.change_seq;
  std::map<int64_t, Change>::iterator it;
  if (changes_.empty() || seq > changes_.rbegin()->first) {
    // The usual case, the author's next change: appended without a search.
    it = changes_.emplace_hint(changes_.end(), seq, change);
  } else {
    bool fresh = false;
    std::tie(it, fresh) = changes_.emplace(seq, change);
    if (!fresh) return false;
  }
  if (seq == contiguous_ + 1) {
    while (it != changes_.end() && it->first == contiguous_ + 1) {
      ++contiguous_;
      ++it;
    }
  }
  return true;
}

const Change* ChangeLog::Find(int64_t seq) const {
  auto it = changes_.find(seq);
  return it == changes_.end() ? nullptr : &it->second;
}

std::vector<const Change*> ChangeLog::Range(int64_t start, int64_t end) const {
  std::vector<const Change*> out;
  for (auto it = changes_.lower_bound(start); it != changes_.end() && it->first <= end; ++it) {
    out.push_back(&it->second);
  }
  return out;
}

int64_t ChangeLog::max_known() const {
  int64_t m = max_held();
  for (const auto& [reporter, seq] : reports_) m = std::max(m, seq);
  return m;
}

std::pair<int64_t, int64_t> ChangeLog::FirstGap() const {
  if (!has_gap()) return {0, -1};
  const int64_t known = max_known();
  const int64_t start = contiguous_ + 1;
  auto next = changes_.upper_bound(contiguous_);
  const int64_t end = next == changes_.end() ? known : next->first - 1;
  return {start, end};
}

}  // namespace dt
