#include "geo/raster_window.h"

#include <algorithm>
#include <cmath>

namespace dt {
namespace {

// Keys' cubic convolution kernel with a = -0.5 (third-order accurate for smooth data).
double Keys(double t) {
  t = std::abs(t);
  if (t <= 1.0) return (1.5 * t - 2.5) * t * t + 1.0;
  if (t < 2.0) return ((-0.5 * t + 2.5) * t - 4.0) * t + 2.0;
  return 0.0;
}

}  // namespace

bool RasterWindow::IsNodata(int c, int r) const {
  const float v = values[static_cast<size_t>(r) * cols + c];
  return std::isnan(v) || (has_nodata && v == nodata);
}

int SupportRadius(Resampling method) { return method == Resampling::kCubic ? 2 : 1; }

std::optional<double> RasterWindow::Sample(double col, double row, Resampling method) const {
  const double fc = std::floor(col);
  const double fr = std::floor(row);
  const double u = col - fc;
  const double v = row - fr;
  const int c0 = static_cast<int>(fc);
  const int r0 = static_cast<int>(fr);
  double wx[4];
  double wy[4];
  int first;  // offset of the first tap from (c0, r0)
  int taps;
  // Repeated edge pixels would spoil cubic's accuracy (to first order): by the edge, bilinear.
  const bool cubic_fits = c0 >= 1 && c0 + 2 < cols && r0 >= 1 && r0 + 2 < rows;
  if (method == Resampling::kCubic && cubic_fits) {
    first = -1;
    taps = 4;
    for (int k = 0; k < 4; ++k) {
      wx[k] = Keys(u - (k - 1));
      wy[k] = Keys(v - (k - 1));
    }
  } else {
    first = 0;
    taps = 2;
    wx[0] = 1.0 - u;
    wx[1] = u;
    wy[0] = 1.0 - v;
    wy[1] = v;
  }
  double sum = 0.0;
  for (int b = 0; b < taps; ++b) {
    if (wy[b] == 0.0) continue;
    const int r = std::clamp(r0 + first + b, 0, rows - 1);
    for (int a = 0; a < taps; ++a) {
      if (wx[a] == 0.0) continue;
      const int c = std::clamp(c0 + first + a, 0, cols - 1);
      if (IsNodata(c, r)) return std::nullopt;
      sum += wx[a] * wy[b] * values[static_cast<size_t>(r) * cols + c];
    }
  }
  return sum;
}

}  // namespace dt
