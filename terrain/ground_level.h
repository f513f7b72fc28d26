// CoarseGround: a level of detail of a ground, so a large world is never drawn post by post.
#pragma once

#include "terrain/height_grid.h"

namespace dt {

// The posts a side a relief picture needs: about one post per pixel of the view's picture.
inline constexpr int kReliefMaxPostsPerSide = 1025;

// `ground` itself if neither side has more than max_posts_per_side posts; otherwise a level of
// detail over the same extent: every `stride`-th post of each row and column (the smallest stride
// that fits), the last row and column included, `stride` times the spacing apart, each square
// taking the soils of the fine square at its lower-left corner. When a side's squares are not a
// multiple of the stride, the coarse grid ends at the last whole stride, short of the far edge by
// less than one coarse spacing. Reads only the posts it keeps: a mapped ground's pages elsewhere
// are never touched. Throws std::invalid_argument unless max_posts_per_side >= 2.
HeightGrid CoarseGround(const HeightGrid& ground, int max_posts_per_side = kReliefMaxPostsPerSide);

// The stride CoarseGround takes: 1 if the ground fits.
int CoarseStride(const HeightGrid& ground, int max_posts_per_side = kReliefMaxPostsPerSide);

}  // namespace dt
