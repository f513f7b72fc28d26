#include "render/montage.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "render/bitmap_font.h"

namespace dt {

Image Montage(std::span<const Image> images, std::span<const std::string> labels,
              const MontageOptions& options) {
  if (images.empty()) throw std::invalid_argument("Montage: no images");
  if (labels.size() != images.size()) {
    throw std::invalid_argument(
        fmt::format("Montage: {} labels for {} images", labels.size(), images.size()));
  }
  if (options.columns < 0 || options.separator_px < 0 || options.label_scale < 1) {
    throw std::invalid_argument(
        fmt::format("Montage: columns {} (>= 0), separator_px {} (>= 0), label_scale {} (>= 1)",
                    options.columns, options.separator_px, options.label_scale));
  }
  int tile_w = 0, tile_h = 0;
  for (size_t k = 0; k < images.size(); ++k) {
    if (images[k].empty())
      throw std::invalid_argument(fmt::format("Montage: image {} is empty", k));
    tile_w = std::max(tile_w, images[k].width());
    tile_h = std::max(tile_h, images[k].height());
  }
  const int n = static_cast<int>(images.size());
  const int cols = options.columns == 0 ? n : std::min(options.columns, n);
  const int rows = (n + cols - 1) / cols;
  const int sep = options.separator_px;
  const int label_h = TextHeightPx(options.label_scale) + 2 * options.label_scale;
  const long long width = static_cast<long long>(cols) * (tile_w + sep) + sep;
  const long long height = static_cast<long long>(rows) * (tile_h + label_h + sep) + sep;
  if (width > Image::kMaxSidePx || height > Image::kMaxSidePx) {
    throw std::invalid_argument(fmt::format("Montage: {} x {} px exceeds {} px per side", width,
                                            height, Image::kMaxSidePx));
  }
  Image out(static_cast<int>(width), static_cast<int>(height), options.background);
  for (int k = 0; k < n; ++k) {
    const int left = sep + (k % cols) * (tile_w + sep);
    const int top = sep + (k / cols) * (tile_h + label_h + sep);
    // Clip the label to its tile by drawing it into a strip of the tile's width.
    Image strip(tile_w, label_h, options.background);
    DrawText(strip, 0, options.label_scale, labels[k], options.label_colour, options.label_scale);
    out.Blit(strip, left, top);
    out.Blit(images[k], left, top + label_h);
  }
  return out;
}

}  // namespace dt
