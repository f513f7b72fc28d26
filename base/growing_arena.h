// GrowingArena: a memory resource for state that only grows while its owner lives (a replica's
// records), its blocks bumped from chunks it maps itself and freed all at once when it dies.
#pragma once

#include <cstddef>
#include <memory_resource>
#include <vector>

#include "base/mapped_memory.h"

namespace dt {

// Every feature a replica learns leaves it a record it keeps for the rest of the exercise. From
// malloc each record costs a search of the free lists that always ends at the top of the heap,
// and the heap's growth a page fault per 4 KiB first written (docs/performance.md). Here a block
// is a pointer bump, and chunks of 2 MiB and more are advised for transparent huge pages: one
// fault per 2 MiB where the kernel grants them (THP "madvise" or "always"), 4 KiB pages where not.
//
// Deallocation does nothing: the memory comes back when the arena is destroyed, so it suits
// containers whose elements are seldom erased. Chunks start at 64 KiB and double up to 32 MiB,
// so a small replica (a test's) maps little; untouched pages of a chunk are never resident.
// Built with AddressSanitizer, every block is its own heap allocation instead, so overruns and
// leaks are still caught. Not thread-safe, like the containers it backs. Throws std::bad_alloc
// when the address space is exhausted, as operator new does.
class GrowingArena final : public std::pmr::memory_resource {
 public:
  static constexpr size_t kFirstChunkBytes = size_t{64} * 1024;
  static constexpr size_t kLargestChunkBytes = size_t{32} * 1024 * 1024;
  static constexpr size_t kHugePageBytes = size_t{2} * 1024 * 1024;

  GrowingArena() = default;
  GrowingArena(const GrowingArena&) = delete;
  GrowingArena& operator=(const GrowingArena&) = delete;

  // Bytes of chunks mapped so far (0 when every block is a heap allocation).
  size_t chunk_bytes() const { return chunk_bytes_; }
  size_t chunk_count() const { return chunks_.size(); }
  // True when blocks come from the heap one by one (an AddressSanitizer build).
  static bool blocks_on_heap();

 private:
  void* do_allocate(size_t bytes, size_t alignment) override;
  void do_deallocate(void* p, size_t bytes, size_t alignment) override;
  bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override {
    return this == &other;
  }
  // Maps a chunk with room for at least `bytes` at any alignment up to `alignment`.
  void NewChunk(size_t bytes, size_t alignment);

  std::vector<MappedMemory> chunks_;
  std::byte* next_ = nullptr;  // the current chunk's first free byte
  std::byte* end_ = nullptr;   // one past its last byte
  size_t next_chunk_bytes_ = kFirstChunkBytes;
  size_t chunk_bytes_ = 0;
};

}  // namespace dt
