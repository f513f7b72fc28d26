// BaseGround: the ground an exercise starts on, the grid and the features every member has from
// the start (a saved terrain used as the exercise's ground), and its digest.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "terrain/feature_params.h"
#include "terrain/height_grid.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"

namespace dt {

// The origin of the base ground's features: no member can have it (sites and hosts start at 1),
// so no member ever issues one of their IDs.
inline constexpr NodeAddress kGroundOrigin{0, 0};

struct BaseGround {
  HeightGrid grid;
  // Sorted by ID, all of origin kGroundOrigin, numbered 1, 2, ...; they place on `grid` in this
  // order (BaseGroundFromTerrain makes them so).
  std::vector<std::pair<FeatureId, FeatureParams>> features;
};

// A loaded terrain as base ground (docs/node.md "Starting from a saved terrain"): the posts as
// they stand, blade work included (earth moves are baked into the grid and are no features of
// the base), and every other feature renumbered under kGroundOrigin in the order of its ID, so
// that it keeps its place among the others (a lower ID's bridge still wins an overlap).
BaseGround BaseGroundFromTerrain(const Terrain& terrain);

// The same base ground from a saved terrain's parts: its posts as they stand (blade work
// included, as a ground cache built from BaseGroundFromTerrain holds them) and the file's
// feature records in ID order (LoadTerrainFileFeatures), renumbered as BaseGroundFromTerrain
// does, earth moves left out.
BaseGround BaseGroundFromParts(HeightGrid grid,
                               const std::vector<std::pair<FeatureId, FeatureParams>>& features);

// A terrain holding the base ground. Throws std::invalid_argument if a feature does not place
// (a BaseGround not made by BaseGroundFromTerrain).
std::unique_ptr<Terrain> MakeTerrain(const BaseGround& base);

// The digest of a terrain holding the base ground and nothing else: the ground's identity.
TerrainDigest ComputeDigest(const BaseGround& base);

}  // namespace dt
