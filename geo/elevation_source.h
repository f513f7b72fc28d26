// ElevationSource: what an exercise asks of an elevation raster ([terrain] elevation_file,
// docs/real-ground.md).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string_view>

namespace dt {

// How posts between the file's pixels are interpolated (docs/real-ground.md "Resampling").
enum class Resampling : uint8_t { kBilinear, kCubic };

// Which part of the file the exercise covers.
enum class AreaKind : uint8_t {
  kWholeFile,  // from the first to the last pixel centre
  kFileCrs,    // area = {x_min, y_min, x_max, y_max} in the file's CRS (its geotransform's x, y)
  kLonLat,     // area = {west, south, east, north} in degrees of WGS-84 longitude and latitude
};

// What becomes of posts whose interpolation touches a nodata pixel.
enum class NodataFill : uint8_t {
  kNone,      // an error naming how many and where
  kNearest,   // the nearest post with data, by grid steps
  kConstant,  // nodata_fill_m
};

struct ElevationSource {
  std::filesystem::path file;  // absolute
  AreaKind area_kind = AreaKind::kWholeFile;
  std::array<double, 4> area{};  // as AreaKind says; unused for kWholeFile
  double spacing_m = 0.0;        // 0: the file's own post spacing
  Resampling resampling = Resampling::kBilinear;
  NodataFill nodata_fill = NodataFill::kNone;
  double nodata_fill_m = 0.0;
  uint64_t max_load_bytes = 0;  // 0: DefaultMaxLoadBytes()
};

// A quarter of the machine's physical memory: what one process may spend loading its ground.
uint64_t DefaultMaxLoadBytes();

std::string_view ResamplingName(Resampling r);

}  // namespace dt
