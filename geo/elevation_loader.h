// ProbeElevation and LoadElevation: an exercise's ground read from any raster GDAL reads.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "geo/elevation_source.h"
#include "geo/ground_georeference.h"
#include "terrain/height_grid.h"

namespace dt {

// What the file and the source make of the ground, found from the file's header alone: the grid,
// where it lies on the Earth and what loading it will read.
struct ElevationLayout {
  int posts_x = 0;
  int posts_z = 0;
  double spacing_m = 0.0;
  std::shared_ptr<const GroundGeoreference> georeference;
  std::string driver;              // GDAL's short name: "GTiff", "DTED", "AAIGrid"
  std::string file_crs_wkt;        // the file's CRS
  bool local_is_file_crs = false;  // the grid is laid in the file's own (metric) projection
  std::array<double, 6> geotransform{};
  int raster_cols = 0;
  int raster_rows = 0;
  // The block of pixels the posts' interpolation reads: columns [col0, col0 + cols) and rows
  // [row0, row0 + rows) of band 1.
  int window_col0 = 0;
  int window_row0 = 0;
  int window_cols = 0;
  int window_rows = 0;
  uint64_t estimated_bytes = 0;  // what loading will hold at its peak, the terrain included
};

// Reads the file's header and georeference and lays out the grid (docs/real-ground.md). Throws
// std::runtime_error naming the file, the sizes and GDAL's message (CPLGetLastErrorMsg) when GDAL
// cannot read the file, when it has no geotransform or CRS, a rotated geotransform or no band;
// std::invalid_argument when the area reaches beyond the file's data or holds fewer than 2 or more
// than kMaxGridPostsPerSide posts a side, or when loading would take more than max_load_bytes.
ElevationLayout ProbeElevation(const ElevationSource& source);

// Reads the window and interpolates every post. Throws std::runtime_error as ProbeElevation if
// GDAL fails; std::invalid_argument naming how many posts have no data and the first few (their
// post indices, terrain and file coordinates) unless source.nodata_fill says how to fill them.
HeightGrid LoadElevation(const ElevationSource& source, const ElevationLayout& layout);

}  // namespace dt
