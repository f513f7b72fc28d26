#include "render/image_diff.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {
namespace {

void CheckSameSize(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height()) {
    throw std::invalid_argument(
        fmt::format("cannot compare a {} x {} px image with a {} x {} px one", a.width(),
                    a.height(), b.width(), b.height()));
  }
}

}  // namespace

ImageDiff DiffImages(const Image& a, const Image& b) {
  CheckSameSize(a, b);
  ImageDiff d;
  d.min_col = a.width();
  d.min_row = a.height();
  d.max_col = -1;
  d.max_row = -1;
  for (int r = 0; r < a.height(); ++r) {
    for (int c = 0; c < a.width(); ++c) {
      const Rgba pa = a.at(c, r), pb = b.at(c, r);
      if (pa == pb) continue;
      ++d.differing_pixels;
      for (int k = 0; k < 4; ++k)
        d.max_channel_delta = std::max(d.max_channel_delta, std::abs(pa[k] - pb[k]));
      d.min_col = std::min(d.min_col, c);
      d.min_row = std::min(d.min_row, r);
      d.max_col = std::max(d.max_col, c);
      d.max_row = std::max(d.max_row, r);
    }
  }
  if (d.differing_pixels == 0) d.min_col = d.min_row = d.max_col = d.max_row = 0;
  return d;
}

Image DiffPicture(const Image& a, const Image& b) {
  CheckSameSize(a, b);
  Image out(a.width(), a.height());
  for (int r = 0; r < a.height(); ++r) {
    for (int c = 0; c < a.width(); ++c) {
      const Rgba pa = a.at(c, r), pb = b.at(c, r);
      if (pa != pb) {
        out.set(c, r, {255, 0, 0, 255});
        continue;
      }
      // Luma, dimmed so red stands out against any terrain colour.
      const int luma = (299 * pa[0] + 587 * pa[1] + 114 * pa[2]) / 1000;
      const auto g = static_cast<uint8_t>(64 + luma / 3);
      out.set(c, r, {g, g, g, 255});
    }
  }
  return out;
}

}  // namespace dt
