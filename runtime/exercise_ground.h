// The exercise's ground: seeded random ground, an elevation file (docs/real-ground.md) or a saved
// terrain (docs/node.md "Starting from a saved terrain"), built in one place.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geo/elevation_loader.h"
#include "terrain/base_ground.h"
#include "terrain/height_grid.h"

namespace dt {

class TomlReader;
struct ExerciseConfig;
struct DisConfig;

// [terrain] elevation_file and its keys, with what the file's header made of them.
struct ElevationTerrain {
  ElevationSource source;
  ElevationLayout layout;  // posts, spacing and georeference, probed at config load
  // [terrain] ground_cache_dir (relative to the exercise file), where the host's processes share
  // the ground as one mapped file (docs/real-ground.md "Large worlds"); empty: the default,
  // GroundCacheDir.
  std::filesystem::path ground_cache_dir;
};

// A ground of more posts than this is mapped from a ground cache file even without
// ground_cache_dir: kMaxPostsPerSide squared, the largest ground each process made for itself.
inline constexpr uint64_t kGroundCachePostsThreshold =
    static_cast<uint64_t>(kMaxPostsPerSide) * kMaxPostsPerSide;

// Where an elevation ground is cached, or empty for none: ground_cache_dir if given; otherwise,
// for a ground beyond kGroundCachePostsThreshold posts, "dynterrain-ground-<uid>" in the system's
// temporary directory (one per host and user); otherwise none (each process reads the file).
std::filesystem::path GroundCacheDir(const ElevationTerrain& elevation);

// Where a ground_file's ground is cached, or empty for none, by the same rule: [terrain]
// ground_cache_dir if given, else the default directory for a ground beyond
// kGroundCachePostsThreshold posts (by the file's header), else none (each process loads the
// file). Needs the header read (ground_file_shape).
std::filesystem::path GroundFileCacheDir(const ExerciseConfig& exercise);

// What a ground_file's cached ground is made from: the file (absolute path, size, modification
// time) and the checksum it ends with, which names its contents; any change names another cache
// file.
std::string GroundFileCacheKey(const std::filesystem::path& file, uint64_t stored_checksum);

// What the cached ground is made from: the file (absolute path, size, modification time), the
// area, spacing, resampling and fill, and the layout; any change names another cache file.
std::string GroundCacheKey(const ElevationTerrain& elevation);

// The [terrain] keys of an elevation file (besides spacing_m, which the random ground shares).
extern const std::vector<std::string> kElevationKeys;

// Reads elevation_file (relative to base_dir), area_crs or area_lonlat_deg, spacing_m,
// resampling, nodata_fill, nodata_fill_m and max_load_mb, and probes the file. Throws
// std::invalid_argument naming the key for a bad value and, for a file GDAL cannot read, without
// a georeference or too large, ProbeElevation's message (file, sizes, GDAL's own message).
// With probe false the file is not opened and `layout` stays empty (GroundReading::kSkip).
ElevationTerrain ReadElevationTerrain(const TomlReader& terrain,
                                      const std::filesystem::path& base_dir, bool probe = true);

// The greatest distance a hand-typed [dis] origin may lie from the file's, metres.
inline constexpr double kOriginToleranceM = 1.0;

// The [dis] origin with an elevation file: the file's, or, if the exercise file typed one, that
// one when it lies within kOriginToleranceM of the file's. Throws std::invalid_argument naming
// both origins and their distance otherwise.
void ApplyFileOrigin(const ElevationTerrain& elevation, bool origin_typed, DisConfig& dis,
                     const std::string& source_name);

// The one place a process builds its ground from the exercise file: the saved terrain of
// [terrain] ground_file with its features, else the elevation file's ground, else seeded random
// ground without features. A ground_file's or elevation file's bare ground is mapped from the
// host's ground cache where GroundFileCacheDir or GroundCacheDir names one (the file read whole by
// the first process that needs it, which builds the cache file; the others map it and read a
// ground_file's feature section alone); otherwise each process reads the file. Every member of an
// exercise must build the same (docs/pdu.md "Ground identity"). Throws std::invalid_argument
// naming the exercise file, the key and the ground_file's path with LoadTerrain's message (a
// damaged file with the offset), as LoadElevation (nodata without a fill, GDAL read errors) and
// as OpenGroundCache. Not for a file read with GroundReading::kSkip (DT_DEMAND).
BaseGround BuildExerciseGround(const ExerciseConfig& exercise);

// What the ground came from, for messages and `status`: "ground_file <path>", "elevation_file
// <path>" or "random seed <n> <x>x<z> posts spacing <m> m relief <m> m".
std::string ExerciseGroundSource(const ExerciseConfig& exercise);

}  // namespace dt
