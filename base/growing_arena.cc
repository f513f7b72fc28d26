#include "base/growing_arena.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <new>

namespace dt {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kBlocksOnHeap = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kBlocksOnHeap = true;
#else
constexpr bool kBlocksOnHeap = false;
#endif
#else
constexpr bool kBlocksOnHeap = false;
#endif

constexpr size_t kPageBytes = 4096;

size_t RoundUp(size_t n, size_t to) { return (n + to - 1) / to * to; }

std::byte* AlignUp(std::byte* p, size_t alignment) {
  const auto address = reinterpret_cast<uintptr_t>(p);
  return p + (RoundUp(address, alignment) - address);
}

}  // namespace

bool GrowingArena::blocks_on_heap() { return kBlocksOnHeap; }

void* GrowingArena::do_allocate(size_t bytes, size_t alignment) {
  if constexpr (kBlocksOnHeap) return ::operator new (bytes, std::align_val_t{alignment});
  std::byte* p = next_ == nullptr ? nullptr : AlignUp(next_, alignment);
  if (p == nullptr || bytes > static_cast<size_t>(end_ - p)) {
    NewChunk(bytes, alignment);
    p = AlignUp(next_, alignment);
  }
  next_ = p + bytes;
  return p;
}

void GrowingArena::do_deallocate(void* p, size_t /*bytes*/, size_t alignment) {
  if constexpr (kBlocksOnHeap) ::operator delete (p, std::align_val_t{alignment});
}

void GrowingArena::NewChunk(size_t bytes, size_t alignment) {
  size_t size = RoundUp(std::max(next_chunk_bytes_, bytes + alignment), kPageBytes);
  const bool huge = size >= kHugePageBytes;
  // A huge chunk is mapped with a huge page to spare, so that a run of `size` aligned to one lies
  // inside it (the spare pages are never written, so never resident).
  if (huge) size = RoundUp(size, kHugePageBytes);
  chunks_.push_back(MappedMemory::Zeroed(huge ? size + kHugePageBytes : size));
  std::byte* start = chunks_.back().data();
  if (huge) {
    start = AlignUp(start, kHugePageBytes);
    // Advice only: refused (THP "never"), the chunk has 4 KiB pages, which is only slower.
    (void)madvise(start, size, MADV_HUGEPAGE);
  }
  next_ = start;
  end_ = start + size;
  chunk_bytes_ += size;
  next_chunk_bytes_ = std::min(next_chunk_bytes_ * 2, kLargestChunkBytes);
}

}  // namespace dt
