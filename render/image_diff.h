// Image diff: how many pixels two images of one size differ in, and where.
#pragma once

#include "render/image.h"

namespace dt {

struct ImageDiff {
  size_t differing_pixels = 0;
  // Bounding box of the differing pixels, inclusive; meaningful only if differing_pixels > 0.
  int min_col = 0;
  int min_row = 0;
  int max_col = 0;
  int max_row = 0;
  int max_channel_delta = 0;  // largest |a - b| over all channels
};

// Compares pixel by pixel (all four channels). Images of different sizes are misuse and throw
// std::invalid_argument with both sizes.
ImageDiff DiffImages(const Image& a, const Image& b);

// A picture of the difference: `a` dimmed to grey, with differing pixels in red, so a person
// sees at a glance where two renderings disagree. Throws like DiffImages.
Image DiffPicture(const Image& a, const Image& b);

}  // namespace dt
