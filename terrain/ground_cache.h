// GroundCache: a ground built once per host into a file every process maps and shares.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/height_grid.h"

namespace dt {

// The file's layout (docs/real-ground.md "Large worlds"): a 4096-byte header, the posts as
// little-endian floats row by row from byte 4096, then, from the next page, the soils as u16, two
// per square. The header holds "DTGROUND", the format version, the shape, the XXH3-128 of the key
// the file was built for, of the bytes after the header, and the ground's digest (ComputeDigest).
inline constexpr size_t kGroundCacheHeaderBytes = 4096;
inline constexpr uint32_t kGroundCacheVersion = 1;

// What a builder removes of the cache directory's older files (docs/real-ground.md "Large
// worlds"): after it builds a file, the other `ground-*.dtg` files of this user not used (opened)
// for more than max_age_days, then, oldest use first, as many as it takes for the user's files to
// fit budget_bytes; the file just built is always kept, as is every other user's file. A process
// still mapping a removed file keeps its pages; the next to ask for it builds it again.
struct GroundCachePruning {
  int max_age_days = 30;
  uint64_t budget_bytes = uint64_t{8} << 30;  // 8 GiB: ten grounds of 10^8 posts
};

struct GroundCacheOpened {
  HeightGrid grid;             // mapped from the file (HeightGrid::Mapped)
  std::filesystem::path file;  // the cache file
  bool built = false;          // this call built the file
  // Why the file was built: "absent", or what was wrong with the one found (a damaged file is
  // never trusted: its size, header and the hash of every byte after the header are checked).
  std::string build_reason;
  // The older files a build removed, each with why ("unused for 41 days", "over the budget").
  std::vector<std::string> removed;
};

// The file in `dir` for `key`: "ground-<XXH3-128 of key, hex>.dtg". The key names everything the
// ground is made from (the source file, its size and time, the area, the spacing, ...), so a
// changed source names another file.
std::filesystem::path GroundCacheFile(const std::filesystem::path& dir, std::string_view key);

// Maps the cache file for `key` in `dir` (made if absent), first building it with `build` if it
// is absent or fails its checks. Processes starting at once are safe: builders take an exclusive
// lock on "<file>.lock" (flock), write "<file>.tmp.<pid>" and rename it into place, so a reader
// sees a whole file or none, and only the first builds. Opening a file marks it used (its
// modification time); a build then prunes the directory by `pruning`. Throws std::runtime_error
// naming the path and errno's text when the directory or file cannot be written or read, and what
// `build` throws.
GroundCacheOpened OpenGroundCache(const std::filesystem::path& dir, std::string_view key,
                                  const std::function<HeightGrid()>& build,
                                  const GroundCachePruning& pruning = {});

}  // namespace dt
