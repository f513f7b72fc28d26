// FeatureTable: the terrain's features by ID, each origin's numbers in a dense array, owning them.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "base/demand.h"
#include "base/feature_id.h"
#include "terrain/feature.h"

namespace dt {

// A node numbers its features 1, 2, ... (docs/protocol.md), so each origin's features sit in an
// array indexed by number: adding the next one writes beside the last, where an open-addressing
// hash table scattered consecutive numbers and missed the cache once per feature (then the
// largest part of Terrain::Add with 10^5 features). An array only grows to a number while it
// stays at least about half full (kDenseSlack slots beyond twice its features), so memory follows
// the feature count whatever the numbers; a number past that (sparse or hostile IDs, a base
// ground's far numbers) is kept in a hash map instead, and moves into the array once the array
// reaches it. Features are owned through pointers, so a Feature* stays valid while the table grows.
class FeatureTable {
 public:
  // An origin's array may reach this many slots beyond twice the features it holds.
  static constexpr size_t kDenseSlack = 64;

  FeatureTable() = default;
  // The moved-from table is left empty: its remembered origin would name the other's entry.
  FeatureTable(FeatureTable&& other) noexcept { *this = std::move(other); }
  FeatureTable& operator=(FeatureTable&& other) noexcept {
    origins_ = std::move(other.origins_);
    sparse_ = std::move(other.sparse_);
    last_key_ = std::exchange(other.last_key_, kNoOrigin);
    last_ = std::exchange(other.last_, nullptr);
    size_ = std::exchange(other.size_, 0);
    other.Clear();
    return *this;
  }

  size_t size() const { return size_; }

  Feature* Find(FeatureId id) const {
    if (const Origin* o = OriginFor(id); o != nullptr && o->Holds(id.number)) {
      return o->dense[o->Index(id.number)].get();
    }
    if (sparse_.empty()) return nullptr;
    const auto it = sparse_.find(id);
    return it == sparse_.end() ? nullptr : it->second.get();
  }

  // Starts fetching the slot where `id` is (or would be) kept, which a caller can overlap with
  // other work before Find or Insert.
  void Prefetch(FeatureId id) const {
    const Origin* o = OriginFor(id);
    if (o == nullptr || !o->Holds(id.number)) return;
    const auto* slot = &o->dense[o->Index(id.number)];
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
    Origin& o = OriginOrNew(id);
    if (!o.Holds(id.number) && !Reaches(o, id.number) && o.count <= 1) Restart(o, id);
    if (!o.Holds(id.number) && Reaches(o, id.number)) Widen(o, id);
    Feature* f = feature.get();
    if (o.Holds(id.number)) {
      auto& slot = o.dense[o.Index(id.number)];
      DT_DEMAND(!slot);
      slot = std::move(feature);
      ++o.count;
    } else {
      DT_DEMAND(sparse_.emplace(id, std::move(feature)).second);
    }
    ++size_;
    return f;
  }

  // Replaces the feature held under `id` (which must be held); returns the new one.
  Feature* Replace(FeatureId id, std::unique_ptr<Feature> feature) {
    std::unique_ptr<Feature>& slot = SlotOf(id);
    DT_DEMAND(slot);  // callers hold the ID
    slot = std::move(feature);
    return slot.get();
  }

  // Destroys the feature under `id`; false if none.
  bool Erase(FeatureId id) {
    if (Origin* o = MutableOriginFor(id); o != nullptr && o->Holds(id.number)) {
      auto& slot = o->dense[o->Index(id.number)];
      if (!slot) return false;
      slot.reset();
      --o->count;
      --size_;
      return true;
    }
    if (sparse_.erase(id) == 0) return false;
    --size_;
    return true;
  }

  void Clear() {
    origins_.clear();
    sparse_.clear();
    last_key_ = kNoOrigin;
    last_ = nullptr;
    size_ = 0;
  }

  // Calls f(const Feature&) for every feature, in no particular order.
  template <typename F>
  void ForEach(F&& f) const {
    for (const auto& [key, o] : origins_) {
      for (const auto& p : o.dense) {
        if (p) f(*p);
      }
    }
    for (const auto& [id, p] : sparse_) f(*p);
  }

  // Slots of every origin's array (held or empty): what the table costs beyond its features.
  size_t dense_slots() const {
    size_t n = 0;
    for (const auto& [key, o] : origins_) n += o.dense.size();
    return n;
  }

 private:
  struct Origin {
    std::vector<std::unique_ptr<Feature>> dense;  // numbers first, first + 1, ...
    uint32_t first = 0;
    size_t count = 0;  // features held in `dense`
    size_t Index(uint32_t number) const { return number - first; }
    // Wraps to a large index below `first`.
    bool Holds(uint32_t number) const { return size_t{number} - first < dense.size(); }
  };
  static constexpr uint64_t kNoOrigin = ~uint64_t{0};
  static uint64_t KeyOf(FeatureId id) { return (uint64_t{id.site} << 16) | id.host; }

  // The origin's entry, or null; the last one found is remembered, as a burst of one origin's
  // features asks for the same one again and again.
  const Origin* OriginFor(FeatureId id) const {
    const uint64_t key = KeyOf(id);
    if (key == last_key_) return last_;
    const auto it = origins_.find(key);
    if (it == origins_.end()) return nullptr;
    last_key_ = key;
    last_ = &it->second;  // node-based: stays valid while other origins are added
    return last_;
  }

  // The table's own entry: the const_cast only drops what OriginFor added.
  Origin* MutableOriginFor(FeatureId id) { return const_cast<Origin*>(OriginFor(id)); }

  Origin& OriginOrNew(FeatureId id) {
    if (Origin* o = MutableOriginFor(id)) return *o;
    const uint64_t key = KeyOf(id);
    Origin& o = origins_[key];
    last_key_ = key;
    last_ = &o;
    return o;
  }

  // May the origin's array, grown to reach `number`, stay about half full or more?
  static bool Reaches(const Origin& o, uint32_t number) {
    if (o.dense.empty()) return true;  // an array of one number to begin with
    const uint64_t end = uint64_t{o.first} + o.dense.size();
    const uint64_t span = number < o.first ? end - number : uint64_t{number} + 1 - o.first;
    return span <= Limit(o);
  }
  static uint64_t Limit(const Origin& o) { return 2 * (uint64_t{o.count} + 1) + kDenseSlack; }

  // Sets the origin's features aside and drops its array, which held one feature at most: an
  // origin's first number seen may be far from the rest (a late joiner hears a live feature,
  // then the older ones played back), and must not keep them all out of the array.
  void Restart(Origin& o, FeatureId id) {
    for (size_t k = 0; k < o.dense.size(); ++k) {
      if (!o.dense[k]) continue;
      const FeatureId held{id.site, id.host, static_cast<uint32_t>(o.first + k)};
      sparse_.emplace(held, std::move(o.dense[k]));
    }
    o.dense = std::vector<std::unique_ptr<Feature>>();
    o.count = 0;
  }

  // Grows the origin's array to reach `id`'s number (doubling the slots, at the end the number is
  // at, within Limit), and moves in the origin's sparse features it now reaches.
  void Widen(Origin& o, FeatureId id) {
    const uint64_t old_first = o.first, old_end = old_first + o.dense.size();
    uint64_t first = old_first, end = old_end;
    if (o.dense.empty()) {
      first = id.number;
      end = first + 16;
    } else if (id.number >= old_end) {
      end = std::max<uint64_t>(uint64_t{id.number} + 1, old_first + 2 * o.dense.size());
      end = std::min(end, old_first + Limit(o));
    } else {
      const uint64_t room = std::max<uint64_t>(old_first - id.number, o.dense.size());
      first = old_first - std::min<uint64_t>({room, old_first, Limit(o) - o.dense.size()});
    }
    end = std::min<uint64_t>(end, uint64_t{UINT32_MAX} + 1);
    std::vector<std::unique_ptr<Feature>> dense(end - first);
    for (size_t k = 0; k < o.dense.size(); ++k)
      dense[old_first - first + k] = std::move(o.dense[k]);
    o.dense = std::move(dense);
    o.first = static_cast<uint32_t>(first);
    if (sparse_.empty()) return;
    for (auto it = sparse_.begin(); it != sparse_.end();) {
      const FeatureId s = it->first;
      if (KeyOf(s) == KeyOf(id) && o.Holds(s.number)) {
        o.dense[o.Index(s.number)] = std::move(it->second);
        ++o.count;
        it = sparse_.erase(it);
      } else {
        ++it;
      }
    }
  }

  std::unique_ptr<Feature>& SlotOf(FeatureId id) {
    if (Origin* o = MutableOriginFor(id); o != nullptr && o->Holds(id.number)) {
      return o->dense[o->Index(id.number)];
    }
    const auto it = sparse_.find(id);
    DT_DEMAND(it != sparse_.end());  // callers hold the ID
    return it->second;
  }

  std::unordered_map<uint64_t, Origin> origins_;
  std::unordered_map<FeatureId, std::unique_ptr<Feature>> sparse_;
  mutable uint64_t last_key_ = kNoOrigin;
  mutable const Origin* last_ = nullptr;
  size_t size_ = 0;
};

}  // namespace dt
