// The terrain file format's constants shared by its reader and writer
// (docs/terrain-file-format.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "terrain/height_grid.h"

namespace dt::terrain_file_format {

// A high first byte catches 7-bit transfers, CR LF catches line-ending conversion, 0x1A stops
// `type` on DOS-like systems (the PNG trick).
inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'D', 'T', 'E', 'R', '\r', '\n', 0x1A};
inline constexpr size_t kVersionOffset = 8;
inline constexpr size_t kGroundLengthOffset = 12;
inline constexpr size_t kFeatureLengthOffset = 20;
inline constexpr int kMaxPosts = kMaxGridPostsPerSide;  // HeightGrid's limit
// Files are read and written in pieces of this size: a ground of 10^8 posts never has a second
// copy in memory, and a piece stays well inside the caches.
inline constexpr size_t kChunkBytes = size_t{1} << 20;

// Bytes of a ground section: the post counts (one for a square grid up to version 3, two from
// version 4), spacing, posts, two soils per square.
inline uint64_t GroundSectionBytes(uint32_t version, uint64_t nx, uint64_t nz) {
  const uint64_t counts = version >= 4 ? 8 : 4;
  return counts + 8 + 4 * nx * nz + 2 * 2 * (nx - 1) * (nz - 1);
}

}  // namespace dt::terrain_file_format
