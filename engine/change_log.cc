#include "engine/change_log.h"

#include <algorithm>
#include <new>

namespace dt {

bool ChangeLog::Insert(const Change& change) {
  const int64_t seq = change.stamp.change_seq;
  const auto slots = static_cast<int64_t>(slot_count_);
  if (Find(seq) != nullptr) return false;
  if (seq >= 1 && seq <= slots) {
    slot(static_cast<size_t>(seq - 1)) = change;
  } else if (seq > slots && seq - slots <= kMaxSlotJump) {
    GrowSlots(static_cast<size_t>(seq));
    slot(static_cast<size_t>(seq - 1)) = change;
  } else {
    aside_.emplace(seq, change);
  }
  ++held_;
  max_held_ = std::max(max_held_, seq);
  while (Find(contiguous_ + 1) != nullptr) ++contiguous_;
  return true;
}

void ChangeLog::GrowSlots(size_t count) {
  while (chunks_.size() * kChunkSlots < count) {
    // Default-initialised, not value-initialised: each slot's optional starts empty, and the
    // 6 KiB of the chunk are not zeroed first. Owned before push_back, which may throw.
    std::unique_ptr<Chunk, ChunkDeleter> chunk(
        new (memory_->allocate(sizeof(Chunk), alignof(Chunk))) Chunk, ChunkDeleter{memory_});
    chunks_.push_back(std::move(chunk));
  }
  slot_count_ = std::max(slot_count_, count);
}

void ChangeLog::ChunkDeleter::operator()(Chunk* chunk) const {
  chunk->~Chunk();
  memory->deallocate(chunk, sizeof(Chunk), alignof(Chunk));
}

bool ChangeLog::Replace(const Change& change) {
  const int64_t seq = change.stamp.change_seq;
  if (seq >= 1 && seq <= static_cast<int64_t>(slot_count_)) {
    auto& held = slot(static_cast<size_t>(seq - 1));
    if (held) {
      *held = change;
      return true;
    }
  }
  auto it = aside_.find(seq);
  if (it == aside_.end()) return false;
  it->second = change;
  return true;
}

std::optional<Change> ChangeLog::Remove(int64_t seq) {
  std::optional<Change> removed;
  if (seq >= 1 && seq <= static_cast<int64_t>(slot_count_)) {
    auto& held = slot(static_cast<size_t>(seq - 1));
    removed.swap(held);  // the slot stays, empty: later slots do not move
  }
  if (!removed) {
    auto it = aside_.find(seq);
    if (it == aside_.end()) return std::nullopt;
    removed = std::move(it->second);
    aside_.erase(it);
  }
  --held_;
  if (seq >= 1) contiguous_ = std::min(contiguous_, seq - 1);
  if (seq == max_held_) {
    // The next held sequence below, aside or in a slot (a scan of empty slots: removing is rare).
    max_held_ = 0;
    if (auto a = aside_.lower_bound(seq); a != aside_.begin()) {
      max_held_ = std::max<int64_t>(0, std::prev(a)->first);
    }
    for (int64_t s = std::min<int64_t>(seq - 1, static_cast<int64_t>(slot_count_)); s > max_held_;
         --s) {
      if (slot(static_cast<size_t>(s - 1))) {
        max_held_ = s;
        break;
      }
    }
  }
  return removed;
}

const Change* ChangeLog::Find(int64_t seq) const {
  if (seq >= 1 && seq <= static_cast<int64_t>(slot_count_)) {
    const auto& held = slot(static_cast<size_t>(seq - 1));
    if (held) return &*held;
  }
  if (aside_.empty()) return nullptr;
  auto it = aside_.find(seq);
  return it == aside_.end() ? nullptr : &it->second;
}

std::vector<const Change*> ChangeLog::Range(int64_t start, int64_t end) const {
  std::vector<const Change*> out;
  const int64_t first = std::max<int64_t>(start, 1);
  const int64_t last = std::min<int64_t>(end, static_cast<int64_t>(slot_count_));
  for (int64_t seq = first; seq <= last; ++seq) {
    const auto& held = slot(static_cast<size_t>(seq - 1));
    if (held) out.push_back(&*held);
  }
  if (!aside_.empty()) {
    const size_t from_slots = out.size();
    for (auto it = aside_.lower_bound(start); it != aside_.end() && it->first <= end; ++it) {
      out.push_back(&it->second);
    }
    if (out.size() != from_slots) {
      std::sort(out.begin(), out.end(), [](const Change* a, const Change* b) {
        return a->stamp.change_seq < b->stamp.change_seq;
      });
    }
  }
  return out;
}

int64_t ChangeLog::max_known() const {
  int64_t m = std::max(max_held(), floor_);
  for (const auto& [reporter, seq] : reports_) m = std::max(m, seq);
  for (const auto& [holder, seq] : held_by_) m = std::max(m, seq);
  return m;
}

std::pair<int64_t, int64_t> ChangeLog::FirstGap() const {
  if (!has_gap()) return {0, -1};
  const int64_t known = max_known();
  const int64_t start = contiguous_ + 1;
  // The next held sequence: a slot is at most kMaxSlotJump past a held one, so this scan is short.
  int64_t next = known + 1;
  for (int64_t seq = start + 1; seq <= static_cast<int64_t>(slot_count_); ++seq) {
    if (slot(static_cast<size_t>(seq - 1))) {
      next = seq;
      break;
    }
  }
  if (auto it = aside_.upper_bound(contiguous_); it != aside_.end()) {
    next = std::min(next, it->first);
  }
  return {start, std::min(known, next - 1)};
}

}  // namespace dt
