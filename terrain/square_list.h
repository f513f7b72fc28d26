// SquareList: the features touching one grid square, the first few held inline.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>

#include "terrain/feature.h"

namespace dt {

// Most squares are touched by one to four features: holding those in the list itself saves the
// elevation query one dependent cache miss (a heap block) per featured square, which on a world
// of 10^8 squares is a miss to memory (docs/real-ground.md "Large worlds"), and saves adding a
// feature an allocation. Features on a 10 m lattice share each square four ways, so four fit.
// Beyond kInline the features all live in one heap array of the list's own, grown by doubling;
// 40 bytes a list either way (the array's pointer and capacity take the inline slots' place).
class SquareList {
 public:
  static constexpr uint32_t kInline = 4;

  SquareList() = default;
  ~SquareList() { Free(); }
  SquareList(SquareList&& other) noexcept { Take(other); }
  SquareList& operator=(SquareList&& other) noexcept {
    if (this != &other) {
      Free();
      Take(other);
    }
    return *this;
  }
  SquareList(const SquareList&) = delete;
  SquareList& operator=(const SquareList&) = delete;

  std::span<const Feature* const> features() const {
    return {capacity_ == 0 ? slots_.inline_features : slots_.heap, size_};
  }
  bool empty() const { return size_ == 0; }

  void push_back(const Feature* feature) {
    if (capacity_ == 0) {
      if (size_ < kInline) {
        slots_.inline_features[size_++] = feature;
        return;
      }
      Reallocate(2 * kInline);
    } else if (size_ == capacity_) {
      Reallocate(2 * capacity_);
    }
    slots_.heap[size_++] = feature;
  }

  // Takes every occurrence of `feature` off the list.
  void erase(const Feature* feature) {
    if (capacity_ == 0) {
      const Feature** end =
          std::remove(slots_.inline_features, slots_.inline_features + size_, feature);
      size_ = static_cast<uint32_t>(end - slots_.inline_features);
      return;
    }
    size_ =
        static_cast<uint32_t>(std::remove(slots_.heap, slots_.heap + size_, feature) - slots_.heap);
    if (size_ <= kInline) {
      const Feature** heap = slots_.heap;  // the inline slots overlay the pointer: copy first
      const Feature* kept[kInline] = {};
      std::copy(heap, heap + size_, kept);
      delete[] heap;
      capacity_ = 0;
      std::copy(kept, kept + kInline, slots_.inline_features);
    }
  }

  // Empty, its heap memory given back.
  void clear() {
    Free();
    size_ = 0;
  }

 private:
  void Reallocate(uint32_t capacity) {
    const Feature** grown = new const Feature*[capacity];
    const Feature* const* from = capacity_ == 0 ? slots_.inline_features : slots_.heap;
    std::copy(from, from + size_, grown);
    Free();
    slots_.heap = grown;
    capacity_ = capacity;
  }
  void Free() {
    if (capacity_ != 0) delete[] slots_.heap;
    capacity_ = 0;
  }
  // Steals `other`'s features and leaves it empty.
  void Take(SquareList& other) {
    size_ = other.size_;
    capacity_ = other.capacity_;
    std::memcpy(&slots_, &other.slots_, sizeof slots_);
    other.size_ = 0;
    other.capacity_ = 0;
  }

  uint32_t size_ = 0;
  uint32_t capacity_ = 0;  // 0: the features are inline
  union Slots {
    const Feature* inline_features[kInline];
    const Feature** heap;  // capacity_ entries
  } slots_ = {};
};

}  // namespace dt
