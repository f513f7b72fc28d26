// TerrainDigest: a canonical 128-bit digest of the whole terrain state, equal across machines.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "terrain/height_grid.h"
#include "terrain/terrain.h"

namespace dt {

// XXH3-128 of the canonical state encoding (docs/terrain.md, "Files and digest"): the ground
// (post counts, spacing, every post's bit pattern, every triangle's soil) and every feature sorted
// by ID with its canonical parameter encoding. Two terrains holding the same state have equal
// digests whatever order their features were added in.
struct TerrainDigest {
  uint64_t high = 0;
  uint64_t low = 0;

  auto operator<=>(const TerrainDigest&) const = default;
  // 32 lower-case hex digits, high half first (XXH128's canonical big-endian form).
  std::string ToHex() const;
  // Parses ToHex's form; nullopt unless exactly 32 hex digits.
  static std::optional<TerrainDigest> FromHex(std::string_view hex);
};

TerrainDigest ComputeDigest(const Terrain& terrain);
// The digest of a terrain holding this ground and no features.
TerrainDigest ComputeDigest(const HeightGrid& ground);

}  // namespace dt

namespace dt {

// ComputeDigest(terrain) remembered: the same digest, worked out again only for what changed. A
// terrain's stamp() names its whole state and ground_stamp() its ground's (both unique across
// terrains), so an unchanged terrain is answered at once and one whose features alone changed
// hashes its features after the saved hash state of its ground: asking every second costs
// O(1), or O(features) after a change, instead of reading 10^8 posts (docs/real-ground.md).
class TerrainDigester {
 public:
  TerrainDigester();
  ~TerrainDigester();
  TerrainDigester(TerrainDigester&&) noexcept;
  TerrainDigester& operator=(TerrainDigester&&) noexcept;

  TerrainDigest Of(const Terrain& terrain);

 private:
  struct GroundState;  // the hash state after the ground (xxhash stays out of this header)
  std::optional<TerrainDigest> digest_;
  uint64_t stamp_ = 0;
  std::unique_ptr<GroundState> ground_;
  uint64_t ground_stamp_ = 0;
};

}  // namespace dt
