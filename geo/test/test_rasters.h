// Test rasters: analytic surfaces written through GDAL at test time (no files fetched).
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace dt::testing {

// A raster to write: `cols` x `rows` pixels whose geotransform is `geotransform` (GDAL's: x of
// the top-left corner, pixel width, 0, y of the top-left corner, 0, pixel height (negative for
// north-up)), in EPSG `epsg`; each pixel holds surface(x, y) at its centre, except `holes`
// (column, row), which hold `nodata`.
struct TestRaster {
  std::string driver = "GTiff";  // or "DTED", "AAIGrid"
  int epsg = 32633;
  int cols = 0;
  int rows = 0;
  std::array<double, 6> geotransform{};
  std::function<double(double x, double y)> surface;
  bool integer = false;  // Int16 pixels (DTED)
  std::optional<double> nodata;
  std::vector<std::pair<int, int>> holes;
  bool georeferenced = true;  // false: no geotransform nor CRS
};

// Writes the raster (through an in-memory dataset and the driver's CreateCopy); throws
// std::runtime_error with GDAL's message if it cannot.
void WriteTestRaster(const std::filesystem::path& path, const TestRaster& raster);

// A fresh empty directory under the system's temporary directory, named after `name`.
std::filesystem::path FreshTestDir(const std::string& name);

}  // namespace dt::testing
