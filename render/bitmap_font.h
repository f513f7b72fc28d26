// Bitmap font: a built-in 5 x 7 pixel font for labels and the scale bar.
#pragma once

#include <string_view>

#include "render/image.h"

namespace dt {

// Glyphs are 5 x 7 font pixels on a 6-pixel advance. Covers digits, upper-case letters, lower-case
// 'k' and 'm' (so "km" and "m" read as units), and " .,-_:/()=+#%". Other lower-case letters are
// drawn as upper case, anything else as '?'.
inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = 6;

// Width and height in image pixels of `text` drawn at `scale` image pixels per font pixel.
int TextWidthPx(std::string_view text, int scale);
inline int TextHeightPx(int scale) { return kGlyphHeight * scale; }

// Draws `text` with its top-left corner at (col, row), clipped to the image. Throws
// std::invalid_argument if scale < 1.
void DrawText(Image& image, int col, int row, std::string_view text, Rgba colour, int scale);

}  // namespace dt
