// Terrain files: save and load the whole terrain (ground and features) in a checked binary format.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "base/result.h"
#include "terrain/terrain.h"

namespace dt {

// docs/terrain-file-format.md describes every byte. The newest version, read and written.
inline constexpr uint32_t kTerrainFileVersion = 4;
// SaveTerrain writes a square grid as version 3, byte for byte what earlier builds wrote (old
// readers still read it, saved files and their checksums do not change); only a grid that is not
// square needs version 4, whose ground section counts posts along x and z apart.
inline constexpr uint32_t kSquareTerrainFileVersion = 3;
// The oldest version LoadTerrain still reads (docs/terrain-file-format.md "Versions").
inline constexpr uint32_t kOldestTerrainFileVersion = 1;
inline constexpr size_t kTerrainFileHeaderBytes = 28;
inline constexpr size_t kTerrainFileChecksumBytes = 8;
// Readers refuse a larger file before reading a byte, and SaveTerrain refuses to write one: 4 GiB
// holds the largest grid (kMaxGridPostsPerSide a side, 2.15 GB) with some 2 GB of features, and
// bounds what `import` reads. Files are read and written a piece at a time, never held whole.
inline constexpr uint64_t kMaxTerrainFileBytes = uint64_t{1} << 32;

// The file's bytes: header, ground section, feature section (sorted by ID), XXH3-64 checksum.
// Version kSquareTerrainFileVersion for a square grid, kTerrainFileVersion otherwise. Held whole
// in memory, for tests and benchmarks (SaveTerrain writes it a piece at a time).
std::vector<uint8_t> EncodeTerrainFile(const Terrain& terrain);

// The file's bytes, all in memory, for tests and benchmarks (LoadTerrain streams instead).
// Checks the magic, version, section sizes and checksum, then rebuilds the ground and adds every
// feature to a fresh Terrain. Any failure returns an error naming the byte offset and what
// failed; nothing is returned half-built. `source_name` prefixes messages.
Result<std::unique_ptr<Terrain>> DecodeTerrainFile(std::span<const uint8_t> bytes,
                                                   std::string_view source_name);

// Writes a temporary file beside `path`, fsyncs it, renames it over `path` and fsyncs the
// directory, so a crash leaves either the old file or the new one, never a partial file. Refuses
// a `path` that exists and is not a regular file (a directory, FIFO, device), and a terrain whose
// file would exceed kMaxTerrainFileBytes.
Status SaveTerrain(const Terrain& terrain, const std::filesystem::path& path);

// Opens `path` as a RegularFile (base/regular_file.h: regular files only, at most
// kMaxTerrainFileBytes, never blocking on a FIFO or device) and decodes it as DecodeTerrainFile
// does, reading it a piece at a time: once for the checksum, once into the terrain's own grid, so
// a ground of 10^8 posts costs no second copy. Never throws.
Result<std::unique_ptr<Terrain>> LoadTerrain(const std::filesystem::path& path);

// What a terrain file's header and the first bytes of its ground section say: the grid's shape,
// and the checksum the file ends with (which names its contents: a ground cache is keyed by it).
struct TerrainFileShape {
  uint32_t version = 0;
  int posts_x = 0;
  int posts_z = 0;
  double spacing_m = 0.0;
  uint64_t file_bytes = 0;
  uint64_t checksum = 0;  // as stored, not computed
};

// Opens `path` as LoadTerrain does and reads the header, the grid's counts and spacing and the
// stored checksum: some 60 bytes, whatever the file's size. Checks what it reads as LoadTerrain
// does, with the same messages and offsets; the posts, soils, features and checksum are not
// checked (LoadTerrain does that). Never throws.
Result<TerrainFileShape> ProbeTerrainFile(const std::filesystem::path& path);

// The feature records of a terrain file in their order (by ID), read without its ground: the
// header and shape are checked as by ProbeTerrainFile, then every record as LoadTerrain checks
// it (same messages and offsets), except that nothing is placed on the ground and the checksum is
// not computed (that would read the ground). For a process whose ground comes from a ground
// cache built from this file by LoadTerrain. Never throws.
Result<std::vector<std::pair<FeatureId, FeatureParams>>> LoadTerrainFileFeatures(
    const std::filesystem::path& path);

}  // namespace dt
