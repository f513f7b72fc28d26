#include "terrain/ground_level.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace dt {

int CoarseStride(const HeightGrid& ground, int max_posts_per_side) {
  if (max_posts_per_side < 2) {
    throw std::invalid_argument(
        fmt::format("max_posts_per_side = {} must be at least 2", max_posts_per_side));
  }
  const int squares = std::max(ground.squares_x(), ground.squares_z());
  // The smallest stride leaving at most max_posts_per_side - 1 squares a side.
  return (squares + max_posts_per_side - 2) / (max_posts_per_side - 1);
}

HeightGrid CoarseGround(const HeightGrid& ground, int max_posts_per_side) {
  const int stride = CoarseStride(ground, max_posts_per_side);
  if (stride <= 1) return ground;
  const int nx = ground.squares_x() / stride + 1;
  const int nz = ground.squares_z() / stride + 1;
  std::vector<float> posts;
  posts.reserve(static_cast<size_t>(nx) * nz);
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) posts.push_back(ground.post(i * stride, j * stride));
  }
  HeightGrid coarse(nx, nz, ground.spacing_m() * stride, std::move(posts));
  for (int j = 0; j + 1 < nz; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      for (TriangleHalf h : {TriangleHalf::kLower, TriangleHalf::kUpper}) {
        coarse.set_soil({i, j}, h, ground.soil({i * stride, j * stride}, h));
      }
    }
  }
  return coarse;
}

}  // namespace dt
