#include "render/scale_bar.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "render/bitmap_font.h"

namespace dt {

double RoundScaleLengthM(double max_length_m) {
  if (!(max_length_m > 0.0) || !std::isfinite(max_length_m)) {
    throw std::invalid_argument(fmt::format("scale length {} m must be positive", max_length_m));
  }
  const double decade = std::pow(10.0, std::floor(std::log10(max_length_m)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= max_length_m) return m * decade;
  }
  return decade;
}

std::string ScaleLabel(double length_m) {
  if (length_m >= 1000.0) return fmt::format("{:g} km", length_m / 1000.0);
  return fmt::format("{:g} m", length_m);
}

void DrawScaleBar(Image& image, double metres_per_pixel) {
  if (!(metres_per_pixel > 0.0) || !std::isfinite(metres_per_pixel)) {
    throw std::invalid_argument(
        fmt::format("scale bar: {} m per pixel must be positive", metres_per_pixel));
  }
  const int scale = std::max(1, image.width() / 640);
  const double length_m = RoundScaleLengthM(image.width() / 5.0 * metres_per_pixel);
  const int bar_px = std::max(1, static_cast<int>(std::lround(length_m / metres_per_pixel)));
  const std::string label = ScaleLabel(length_m);
  const int pad = 3 * scale, bar_h = 4 * scale, text_h = TextHeightPx(scale);
  const int panel_w = std::max(bar_px, TextWidthPx(label, scale)) + 2 * pad;
  const int panel_h = text_h + bar_h + 3 * pad;
  const int left = 2 * pad, bottom = image.height() - 2 * pad;
  const int top = bottom - panel_h;
  const Rgba white{255, 255, 255, 255}, black{0, 0, 0, 255};
  image.FillRect(left, top, left + panel_w, bottom, white);
  DrawText(image, left + pad, top + pad, label, black, scale);
  const int bar_top = top + 2 * pad + text_h;
  // Outlined, with the left and right quarters filled, so the length reads at a glance.
  image.FillRect(left + pad, bar_top, left + pad + bar_px, bar_top + bar_h, black);
  image.FillRect(left + pad + bar_px / 4, bar_top + scale, left + pad + bar_px / 2,
                 bar_top + bar_h - scale, white);
  image.FillRect(left + pad + 3 * bar_px / 4, bar_top + scale, left + pad + bar_px - scale,
                 bar_top + bar_h - scale, white);
}

}  // namespace dt
