// Elevation import: ESRI ASCII grids (.asc) and binary PGM (P5) heightmaps to a HeightGrid.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

#include "base/result.h"
#include "terrain/height_grid.h"

namespace dt {

// ESRI ASCII grid: header lines ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter, cellsize,
// optional NODATA_value (keys case-insensitive, any order), then nrows lines of ncols numbers,
// the first line being the northernmost row. The grid must be square (ncols == nrows); cellsize
// becomes spacing_m; the corner is checked but not kept (our terrain starts at x = z = 0).
// A cell holding the NODATA value is refused, never filled. Errors name the line (1-based).
Result<HeightGrid> ParseAsc(std::string_view text, std::string_view source_name,
                            Material soil = Material::kGrass);
Result<HeightGrid> ImportAsc(const std::filesystem::path& path, Material soil = Material::kGrass);

// How grey levels of a PGM become elevations: y = base_elevation_m + level * metres_per_level.
// The defaults map a 16-bit image onto 0 .. 6553.5 m in 0.1 m steps (docs/terrain.md).
struct PgmImportOptions {
  double spacing_m = 10.0;
  double metres_per_level = 0.1;
  double base_elevation_m = 0.0;
  Material soil = Material::kGrass;
};

// Binary PGM "P5": maxval 1..255 gives one byte per sample, 256..65535 two bytes big-endian.
// The image must be square; its first row is the northernmost; nothing may follow the raster.
// Errors name the byte offset (0-based). Bad options (non-finite, spacing or scale <= 0, a
// soil that is not a soil) throw std::invalid_argument.
Result<HeightGrid> ParsePgm(std::span<const uint8_t> bytes, std::string_view source_name,
                            const PgmImportOptions& options = {});
Result<HeightGrid> ImportPgm(const std::filesystem::path& path,
                             const PgmImportOptions& options = {});

}  // namespace dt
