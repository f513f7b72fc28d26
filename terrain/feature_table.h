// FeatureTable: the terrain's features by ID, an open-addressing hash table owning them.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "base/demand.h"
#include "base/feature_id.h"
#include "terrain/feature.h"

namespace dt {

// Slots are (ID, owner) pairs in one array, probed linearly; a slot is empty when it owns no
// feature. A lookup reads one or two neighbouring slots instead of chasing a bucket list, and
// growing copies the array in order instead of visiting every list node: with 10^5 features the
// node-based std::unordered_map's rehashes and finds were ≈ 10 % of applying a received change.
// Features are owned through pointers, so a Feature* stays valid while the table grows.
class FeatureTable {
 public:
  size_t size() const { return size_; }

  Feature* Find(FeatureId id) const {
    if (size_ == 0) return nullptr;
    for (size_t i = Home(id);; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (!s.feature) return nullptr;
      if (s.id == id) return s.feature.get();
    }
  }

  // Starts fetching the slot where a lookup of `id` begins: in a table of 10^5 features that
  // slot is a miss, which a caller can overlap with other work before Find or Insert.
  void Prefetch(FeatureId id) const {
    if (size_ == 0) return;
    const Slot* slot = &slots_[Home(id)];
#if defined(__x86_64__)
    // Volatile: the compiler moves __builtin_prefetch past the caller's next call, after which
    // the fetch overlaps nothing.
    asm volatile("prefetcht0 %0" : : "m"(*slot));
#else
    __builtin_prefetch(slot);
#endif
  }

  // Takes `feature` under `id`; the ID must not be held (checked: DT_DEMAND).
  Feature* Insert(FeatureId id, std::unique_ptr<Feature> feature) {
    DT_DEMAND(feature);
    if ((size_ + 1) * 4 > slots_.size() * 3) Grow();
    size_t i = Home(id);
    for (; slots_[i].feature; i = (i + 1) & mask_) {
      DT_DEMAND(slots_[i].id != id);
    }
    slots_[i] = {id, std::move(feature)};
    ++size_;
    return slots_[i].feature.get();
  }

  // Replaces the feature held under `id` (which must be held); returns the new one.
  Feature* Replace(FeatureId id, std::unique_ptr<Feature> feature) {
    Slot& s = slots_[IndexOf(id)];
    s.feature = std::move(feature);
    return s.feature.get();
  }

  // Destroys the feature under `id`; false if none.
  bool Erase(FeatureId id) {
    if (Find(id) == nullptr) return false;
    size_t hole = IndexOf(id);
    slots_[hole] = {};
    --size_;
    // Backward-shift deletion: later slots of the same probe run move into the hole, so no
    // lookup ever stops early at it (no tombstones needed).
    for (size_t j = (hole + 1) & mask_; slots_[j].feature; j = (j + 1) & mask_) {
      const size_t home = Home(slots_[j].id);
      // Movable when its home is not cyclically within (hole, j].
      const bool stays = hole <= j ? (home > hole && home <= j) : (home > hole || home <= j);
      if (stays) continue;
      slots_[hole] = std::move(slots_[j]);
      hole = j;
    }
    return true;
  }

  void Clear() {
    slots_.clear();
    mask_ = 0;
    shift_ = 64;
    size_ = 0;
  }

  // Calls f(const Feature&) for every feature, in no particular order.
  template <typename F>
  void ForEach(F&& f) const {
    for (const Slot& s : slots_) {
      if (s.feature) f(*s.feature);
    }
  }

 private:
  struct Slot {
    FeatureId id;
    std::unique_ptr<Feature> feature;
  };

  // Fibonacci hashing of the ID's hash: consecutive numbers land far apart, so the runs of
  // different origins do not merge into long probe sequences.
  size_t Home(FeatureId id) const {
    const uint64_t h = std::hash<FeatureId>{}(id)*0x9E3779B97F4A7C15ull;
    return static_cast<size_t>(h >> shift_) & mask_;
  }

  size_t IndexOf(FeatureId id) const {
    for (size_t i = Home(id);; i = (i + 1) & mask_) {
      DT_DEMAND(slots_[i].feature);  // callers hold the ID
      if (slots_[i].id == id) return i;
    }
  }

  void Grow() {
    const size_t capacity = slots_.empty() ? 64 : slots_.size() * 2;
    std::vector<Slot> old = std::move(slots_);
    slots_ = std::vector<Slot>(capacity);
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    for (Slot& s : old) {
      if (!s.feature) continue;
      size_t i = Home(s.id);
      while (slots_[i].feature) i = (i + 1) & mask_;
      slots_[i] = std::move(s);
    }
  }

  std::vector<Slot> slots_;  // a power of two long, at most 3/4 full
  size_t mask_ = 0;
  int shift_ = 64;
  size_t size_ = 0;
};

}  // namespace dt
