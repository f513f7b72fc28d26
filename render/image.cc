#include "render/image.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"

namespace dt {

Image::Image(int width_px, int height_px, Rgba fill) {
  if (width_px <= 0 || height_px <= 0 || width_px > kMaxSidePx || height_px > kMaxSidePx) {
    throw std::invalid_argument(
        fmt::format("image size {} x {} px is outside 1..{}", width_px, height_px, kMaxSidePx));
  }
  width_ = width_px;
  height_ = height_px;
  bytes_.resize(static_cast<size_t>(width_px) * static_cast<size_t>(height_px) * 4);
  for (size_t k = 0; k < bytes_.size(); k += 4) std::copy(fill.begin(), fill.end(), &bytes_[k]);
}

Rgba Image::at(int col, int row) const {
  DT_DEMAND(Contains(col, row));
  const size_t o = Offset(col, row);
  return {bytes_[o], bytes_[o + 1], bytes_[o + 2], bytes_[o + 3]};
}

void Image::set(int col, int row, Rgba rgba) {
  DT_DEMAND(Contains(col, row));
  std::copy(rgba.begin(), rgba.end(), &bytes_[Offset(col, row)]);
}

void Image::FillRect(int col0, int row0, int col1, int row1, Rgba rgba) {
  col0 = std::max(col0, 0);
  row0 = std::max(row0, 0);
  col1 = std::min(col1, width_);
  row1 = std::min(row1, height_);
  for (int r = row0; r < row1; ++r) {
    for (int c = col0; c < col1; ++c) set(c, r, rgba);
  }
}

void Image::Blit(const Image& src, int col, int row) {
  for (int r = 0; r < src.height(); ++r) {
    const int dr = row + r;
    if (dr < 0 || dr >= height_) continue;
    for (int c = 0; c < src.width(); ++c) SetClipped(col + c, dr, src.at(c, r));
  }
}

}  // namespace dt
