// ReliefTile: one relief tile's ground and features, taken from the terrain on the view's loop,
// and its picture, drawn from them on another thread.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "base/rect.h"
#include "base/result.h"
#include "render/renderer.h"
#include "terrain/terrain.h"
#include "view/relief_pyramid.h"

namespace dt {

struct ReliefTileJob {
  TileKey key;
  int64_t version = 0;
  // The tile's posts, and a margin holding every feature drawn, at the tile's sample stride,
  // with post (0, 0) at the terrain's post (first_i, first_j); soils taken likewise.
  HeightGrid ground{2, 1.0};
  int first_i = 0;
  int first_j = 0;
  // The features touching the tile, moved into the tile's grid (x less first_i's x, z less
  // first_j's z), in ID order. Blade work is in the posts.
  std::vector<std::pair<FeatureId, FeatureParams>> features;
  Rect area;  // the tile's square, in the tile grid's coordinates
  // The whole ground's lowest and highest post (as sampled for level 0), so every tile is tinted
  // alike and neighbours meet without a seam.
  std::pair<double, double> elevation_range_m{0.0, 0.0};
};

// The lowest and highest of the posts level 0's tile samples: the ground's range to a sample a
// pixel, without reading the whole grid.
std::pair<double, double> SampledElevationRange(const HeightGrid& ground,
                                                const ReliefPyramid& pyramid);

// On the view's loop (the terrain is the loop's alone): the tile's posts at its level's sample
// stride and the features touching it. Reads between kTilePx^2 and (2 kTilePx)^2 posts and
// squares whatever the level (the stride is whole posts): never the whole grid. At a coarse level
// (stride > 1) a feature is found when it spans a stride in both directions; smaller ones are
// narrower than a pixel and left out. A feature reaching further than a tile's side beyond the tile
// is left out of its relief (its outline still shows over it). Throws std::invalid_argument unless
// the key is a tile of the pyramid and the pyramid the terrain's.
ReliefTileJob SampleReliefTile(const Terrain& terrain, const ReliefPyramid& pyramid,
                               const TileKey& key, int64_t version,
                               std::pair<double, double> elevation_range_m);

// On any one thread with its own renderer: the tile, kTilePx a side, as PNG bytes. Beyond the
// terrain the picture has the renderer's background.
Result<std::string> RenderReliefTile(Renderer& renderer, const ReliefTileJob& job);

}  // namespace dt
