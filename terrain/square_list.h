// SquareList: the features touching one grid square, the first few held inline.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "terrain/feature.h"

namespace dt {

// Most squares are touched by one to three features: holding those in the list itself saves the
// elevation query one dependent cache miss (the heap block of a std::vector) per featured square,
// which on a world of 10^8 squares is a miss to memory (docs/real-ground.md "Large worlds").
// Beyond kInline the features all live in a vector of their own; 40 bytes a list.
class SquareList {
 public:
  static constexpr uint32_t kInline = 3;

  std::span<const Feature* const> features() const {
    if (size_ <= kInline) return {inline_, size_};
    return *more_;
  }
  bool empty() const { return size_ == 0; }

  void push_back(const Feature* feature) {
    if (size_ < kInline) {
      inline_[size_++] = feature;
      return;
    }
    if (size_ == kInline) {
      more_ = std::make_unique<std::vector<const Feature*>>(inline_, inline_ + kInline);
    }
    more_->push_back(feature);
    ++size_;
  }

  // Takes every occurrence of `feature` off the list.
  void erase(const Feature* feature) {
    if (size_ <= kInline) {
      const Feature** end = std::remove(inline_, inline_ + size_, feature);
      size_ = static_cast<uint32_t>(end - inline_);
      return;
    }
    more_->erase(std::remove(more_->begin(), more_->end(), feature), more_->end());
    size_ = static_cast<uint32_t>(more_->size());
    if (size_ <= kInline) {
      std::copy(more_->begin(), more_->end(), inline_);
      more_.reset();
    }
  }

  // Empty, its heap memory given back.
  void clear() {
    size_ = 0;
    more_.reset();
  }

 private:
  uint32_t size_ = 0;
  const Feature* inline_[kInline] = {};
  std::unique_ptr<std::vector<const Feature*>> more_;  // every feature once size_ > kInline
};

}  // namespace dt
