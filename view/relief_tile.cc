#include "view/relief_tile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

#include <fmt/format.h>

#include "render/camera.h"
#include "render/png_io.h"

namespace dt {
namespace {

// The first and last post of an axis of the tile grid: multiples of the stride (so neighbouring
// tiles sample the same posts and meet without a seam), within the terrain, at least two posts.
std::pair<int, int> PostSpan(double min_m, double max_m, double spacing_m, int stride, int posts) {
  const int last = (posts - 1) / stride * stride;  // the last post the stride reaches
  int lo = static_cast<int>(std::floor(std::max(0.0, min_m) / (stride * spacing_m))) * stride;
  int hi = static_cast<int>(std::ceil(max_m / (stride * spacing_m))) * stride;
  lo = std::clamp(lo, 0, last);
  hi = std::clamp(hi, 0, last);
  if (hi == lo) {
    if (lo + stride <= last) {
      hi = lo + stride;
    } else {
      lo -= stride;
    }
  }
  return {lo, hi};
}

FeatureParams Moved(FeatureParams p, double dx_m, double dz_m) {
  p.x_m -= dx_m;
  p.z_m -= dz_m;
  for (FeaturePoint& q : p.points) {
    q.x_m -= dx_m;
    q.z_m -= dz_m;
  }
  return p;
}

}  // namespace

std::pair<double, double> SampledElevationRange(const HeightGrid& ground,
                                                const ReliefPyramid& pyramid) {
  const int stride = pyramid.SampleStride(0);
  double lo = ground.post(0, 0), hi = lo;
  for (int j = 0; j < ground.posts_z(); j += stride) {
    for (int i = 0; i < ground.posts_x(); i += stride) {
      lo = std::min<double>(lo, ground.post(i, j));
      hi = std::max<double>(hi, ground.post(i, j));
    }
  }
  return {lo, hi};
}

ReliefTileJob SampleReliefTile(const Terrain& terrain, const ReliefPyramid& pyramid,
                               const TileKey& key, int64_t version,
                               std::pair<double, double> elevation_range_m) {
  const HeightGrid& g = terrain.ground();
  if (!pyramid.Valid(key) || pyramid.spacing_m() != g.spacing_m() ||
      pyramid.size_x_m() != g.size_x_m() || pyramid.size_z_m() != g.size_z_m()) {
    throw std::invalid_argument(fmt::format(
        "relief tile {} of a {} x {} m pyramid asked of a {} x {} m terrain", key.ToString(),
        pyramid.size_x_m(), pyramid.size_z_m(), g.size_x_m(), g.size_z_m()));
  }
  const double s = g.spacing_m();
  // A stride of a whole side would leave fewer than two posts.
  const int stride =
      std::max(1, std::min({pyramid.SampleStride(key.level), g.squares_x(), g.squares_z()}));
  const Rect tile = pyramid.TileRect(key);
  const Rect on{tile.min_x, tile.min_z, std::min(tile.max_x, g.size_x_m()),
                std::min(tile.max_z, g.size_z_m())};
  const double pixel_m = pyramid.metres_per_pixel(key.level);
  const Rect reach = tile.Expanded(pyramid.side_m(key.level));

  // The features on the tile's squares, every stride-th square each way.
  std::unordered_set<const Feature*> seen;
  std::vector<const Feature*> kept;
  Rect needed = on;
  const int i_lo = static_cast<int>(std::floor(on.min_x / s));
  const int j_lo = static_cast<int>(std::floor(on.min_z / s));
  const int i_hi = std::min(g.squares_x() - 1, static_cast<int>(std::ceil(on.max_x / s)) - 1);
  const int j_hi = std::min(g.squares_z() - 1, static_cast<int>(std::ceil(on.max_z / s)) - 1);
  for (int j = j_lo / stride * stride; j <= j_hi; j += stride) {
    for (int i = i_lo / stride * stride; i <= i_hi; i += stride) {
      for (const Feature* f : terrain.FeaturesInSquare({i, j})) {
        if (!seen.insert(f).second || f->type() == FeatureType::kEarthMove) continue;
        const Rect b = f->Bounds();
        if (stride > 1 && std::max(b.max_x - b.min_x, b.max_z - b.min_z) < pixel_m) continue;
        if (b.min_x < reach.min_x || b.min_z < reach.min_z || b.max_x > reach.max_x ||
            b.max_z > reach.max_z) {
          continue;
        }
        kept.push_back(f);
        needed = needed.Union(b);
      }
    }
  }
  std::sort(kept.begin(), kept.end(),
            [](const Feature* a, const Feature* b) { return a->id() < b->id(); });

  const auto [i0, i1] = PostSpan(needed.min_x, needed.max_x, s, stride, g.posts_x());
  const auto [j0, j1] = PostSpan(needed.min_z, needed.max_z, s, stride, g.posts_z());
  const int mx = (i1 - i0) / stride + 1, mz = (j1 - j0) / stride + 1;
  std::vector<float> posts(static_cast<size_t>(mx) * static_cast<size_t>(mz));
  for (int jj = 0; jj < mz; ++jj) {
    for (int ii = 0; ii < mx; ++ii)
      posts[static_cast<size_t>(jj) * mx + ii] = g.post(i0 + ii * stride, j0 + jj * stride);
  }
  ReliefTileJob job{key, version, HeightGrid(mx, mz, stride * s, std::move(posts)), i0, j0, {}, {}};
  for (int jj = 0; jj + 1 < mz; ++jj) {
    for (int ii = 0; ii + 1 < mx; ++ii) {
      const SquareIndex fine{i0 + ii * stride, j0 + jj * stride};
      for (TriangleHalf h : {TriangleHalf::kLower, TriangleHalf::kUpper})
        job.ground.set_soil({ii, jj}, h, g.soil(fine, h));
    }
  }
  const double ox = i0 * s, oz = j0 * s;
  for (const Feature* f : kept) job.features.emplace_back(f->id(), Moved(f->params(), ox, oz));
  job.area = {tile.min_x - ox, tile.min_z - oz, tile.max_x - ox, tile.max_z - oz};
  job.elevation_range_m = elevation_range_m;
  return job;
}

Result<std::string> RenderReliefTile(Renderer& renderer, const ReliefTileJob& job) {
  // The same features in the same order place alike (docs/protocol.md "Materialisation"); one
  // that does not fit the tile's coarser ground is left out of the picture.
  Terrain terrain(job.ground);
  for (const auto& [id, params] : job.features) (void)terrain.Add(id, params);
  RenderOptions options;
  options.scale_bar = false;
  options.elevation_range_m = job.elevation_range_m;
  try {
    const Image image = renderer.Render(terrain, std::vector<VehicleSprite>{},
                                        Camera::MapOf(job.area, ReliefPyramid::kTilePx), options);
    return EncodePng(image);
  } catch (const std::exception& e) {
    return Error{fmt::format("relief tile {}: {}", job.key.ToString(), e.what())};
  }
}

}  // namespace dt
