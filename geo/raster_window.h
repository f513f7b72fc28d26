// RasterWindow: a block of a raster's pixels in memory, sampled bilinearly or by cubic convolution.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "geo/elevation_source.h"

namespace dt {

// Pixel (c, r) of the window holds values[r * cols + c]; its centre is at window coordinates
// (c, r). Nodata pixels are those equal to `nodata` (when has_nodata) and every NaN.
struct RasterWindow {
  int cols = 0;
  int rows = 0;
  std::vector<float> values;
  bool has_nodata = false;
  float nodata = 0.0f;

  bool IsNodata(int c, int r) const;
  // The value at window coordinates (col, row), interpolated by `method` (docs/real-ground.md
  // "Resampling"): bilinear from the 2 x 2 pixels around the point, cubic convolution (Keys,
  // a = -0.5, as GDAL's "cubic") from the 4 x 4, or bilinear where those reach beyond the
  // window (within a pixel of its edge). Bilinear beyond the edge (to half a pixel) repeats it.
  // nullopt when a pixel with a non-zero weight is nodata.
  std::optional<double> Sample(double col, double row, Resampling method) const;
};

// Pixels the interpolation of `method` reads on each side of a point: 1 (bilinear), 2 (cubic).
int SupportRadius(Resampling method);

}  // namespace dt
