// Tests GrowingArena: aligned, disjoint blocks that keep what was written to them, chunks that
// grow, and a std::pmr container that lives in it.
#include "base/growing_arena.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <vector>

#include <gtest/gtest.h>

namespace dt {
namespace {

struct Block {
  std::byte* p;
  size_t bytes;
  size_t alignment;
  unsigned char fill;
};

TEST(GrowingArenaTest, BlocksAreAlignedDisjointAndKeepTheirContents) {
  GrowingArena arena;
  std::vector<Block> blocks;
  const size_t sizes[] = {1, 8, 24, 200, 4096, 70000};
  const size_t alignments[] = {1, 8, 16, 64, 4096};
  for (int round = 0; round < 300; ++round) {
    const size_t bytes = sizes[round % std::size(sizes)];
    const size_t alignment = alignments[round % std::size(alignments)];
    auto* p = static_cast<std::byte*>(arena.allocate(bytes, alignment));
    ASSERT_EQ(reinterpret_cast<uintptr_t>(p) % alignment, 0u) << bytes << " at " << alignment;
    const auto fill = static_cast<unsigned char>(round);
    std::memset(p, fill, bytes);
    blocks.push_back({p, bytes, alignment, fill});
  }
  // Every block still holds its own fill: none overlaps another.
  for (const Block& b : blocks) {
    for (size_t i = 0; i < b.bytes; ++i) {
      ASSERT_EQ(static_cast<unsigned char>(b.p[i]), b.fill) << "block of " << b.bytes;
    }
  }
  // Given back with the size and alignment they were asked for, as memory_resource requires.
  for (const Block& b : blocks) arena.deallocate(b.p, b.bytes, b.alignment);
}

TEST(GrowingArenaTest, ChunksDoubleUpToTheLargestAndABigBlockGetsOneOfItsOwn) {
  if (GrowingArena::blocks_on_heap()) GTEST_SKIP() << "every block is a heap allocation here";
  GrowingArena arena;
  EXPECT_EQ(arena.chunk_count(), 0u);  // nothing mapped until asked
  (void)arena.allocate(16, 8);
  EXPECT_EQ(arena.chunk_count(), 1u);
  EXPECT_EQ(arena.chunk_bytes(), GrowingArena::kFirstChunkBytes);
  // Filling the first chunk maps a second of twice its size.
  for (size_t used = 16; used < GrowingArena::kFirstChunkBytes; used += 1024) {
    (void)arena.allocate(1024, 8);
  }
  EXPECT_EQ(arena.chunk_count(), 2u);
  EXPECT_EQ(arena.chunk_bytes(), 3 * GrowingArena::kFirstChunkBytes);
  // A block larger than the next chunk would be gets a chunk that holds it, in whole huge pages.
  const size_t big = 5 * GrowingArena::kHugePageBytes + 1;
  auto* p = static_cast<std::byte*>(arena.allocate(big, 64));
  std::memset(p, 0x5a, big);
  EXPECT_EQ(arena.chunk_count(), 3u);
  EXPECT_EQ(arena.chunk_bytes() - 3 * GrowingArena::kFirstChunkBytes,
            6 * GrowingArena::kHugePageBytes);
  // Chunk sizes stop doubling at the largest.
  for (int i = 0; i < 12; ++i) (void)arena.allocate(GrowingArena::kLargestChunkBytes / 2, 8);
  const size_t before = arena.chunk_bytes();
  (void)arena.allocate(GrowingArena::kLargestChunkBytes - 64, 8);
  EXPECT_EQ(arena.chunk_bytes() - before, GrowingArena::kLargestChunkBytes);
}

TEST(GrowingArenaTest, APmrMapLivesInIt) {
  GrowingArena arena;
  std::pmr::map<int, std::vector<int>> m(&arena);
  for (int i = 0; i < 20000; ++i) m.try_emplace(i, std::vector<int>(3, i));
  m.erase(17);  // deallocation does nothing, and must not break the map
  ASSERT_EQ(m.size(), 19999u);
  int64_t sum = 0;
  for (const auto& [k, v] : m) sum += k + v[2];
  EXPECT_EQ(sum, 2 * (int64_t{19999} * 20000 / 2 - 17));
  if (!GrowingArena::blocks_on_heap()) {
    EXPECT_GT(arena.chunk_bytes(), 0u);
  }
}

}  // namespace
}  // namespace dt
