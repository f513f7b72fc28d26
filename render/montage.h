// Montage: several images side by side in one picture, each under its label.
#pragma once

#include <span>
#include <string>

#include "render/image.h"

namespace dt {

struct MontageOptions {
  int columns = 0;       // images per row; 0 puts them all in one row
  int separator_px = 4;  // gap between tiles and around the border
  int label_scale = 2;   // image pixels per font pixel of the labels
  Rgba background = {40, 40, 40, 255};
  Rgba label_colour = {255, 255, 255, 255};
};

// Tiles the images left to right, top to bottom; each tile is as large as the largest image and
// carries its label in a strip above it (labels wider than the tile are cut). Throws
// std::invalid_argument if there are no images, an image is empty, the label count differs from
// the image count, the options are out of range, or the result exceeds Image::kMaxSidePx.
Image Montage(std::span<const Image> images, std::span<const std::string> labels,
              const MontageOptions& options = {});

}  // namespace dt
