// Image: an RGBA8 picture in memory, row 0 at the top.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dt {

using Rgba = std::array<uint8_t, 4>;

// Pixels stored row by row from the top-left corner, 4 bytes (R, G, B, A) each.
class Image {
 public:
  Image() = default;
  // Throws std::invalid_argument unless both sizes are positive and at most kMaxSidePx.
  Image(int width_px, int height_px, Rgba fill = {0, 0, 0, 255});

  static constexpr int kMaxSidePx = 16384;

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0; }
  bool Contains(int col, int row) const {
    return col >= 0 && row >= 0 && col < width_ && row < height_;
  }

  // Unchecked in release: callers stay inside (Contains) as a matter of invariant.
  Rgba at(int col, int row) const;
  void set(int col, int row, Rgba rgba);
  // Sets the pixel if it lies inside the image; drawing functions clip through this.
  void SetClipped(int col, int row, Rgba rgba) {
    if (Contains(col, row)) set(col, row, rgba);
  }
  // Fills the rectangle [col0, col1) x [row0, row1), clipped to the image.
  void FillRect(int col0, int row0, int col1, int row1, Rgba rgba);
  // Copies `src` with its top-left corner at (col, row), clipped to this image.
  void Blit(const Image& src, int col, int row);

  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t>& bytes() { return bytes_; }

  bool operator==(const Image&) const = default;

 private:
  size_t Offset(int col, int row) const {
    return (static_cast<size_t>(row) * static_cast<size_t>(width_) + static_cast<size_t>(col)) * 4;
  }

  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> bytes_;
};

}  // namespace dt
