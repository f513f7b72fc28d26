#include "terrain/base_ground.h"

#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "terrain/feature.h"

namespace dt {

namespace {

// Numbers the features under kGroundOrigin in their order, but earth moves (already in the posts).
void AddRenumbered(const FeatureParams& params, BaseGround& base) {
  if (params.type == FeatureType::kEarthMove) return;
  const auto number = static_cast<uint32_t>(base.features.size() + 1);
  base.features.emplace_back(FeatureId{kGroundOrigin.site, kGroundOrigin.host, number}, params);
}

}  // namespace

BaseGround BaseGroundFromTerrain(const Terrain& terrain) {
  BaseGround base{terrain.ground(), {}};
  for (const Feature* f : terrain.FeaturesById()) AddRenumbered(f->params(), base);
  return base;
}

BaseGround BaseGroundFromParts(HeightGrid grid,
                               const std::vector<std::pair<FeatureId, FeatureParams>>& features) {
  BaseGround base{std::move(grid), {}};
  base.features.reserve(features.size());
  for (const auto& [id, params] : features) AddRenumbered(params, base);
  return base;
}

std::unique_ptr<Terrain> MakeTerrain(const BaseGround& base) {
  auto terrain = std::make_unique<Terrain>(base.grid);
  for (const auto& [id, params] : base.features) {
    if (Status s = terrain->Add(id, params); !s) {
      throw std::invalid_argument(fmt::format("base ground feature {} does not place: {}",
                                              id.ToString(), s.error().message));
    }
  }
  return terrain;
}

TerrainDigest ComputeDigest(const BaseGround& base) {
  if (base.features.empty()) return ComputeDigest(base.grid);
  return ComputeDigest(*MakeTerrain(base));
}

}  // namespace dt
