#include "terrain/base_ground.h"

#include <stdexcept>

#include <fmt/format.h>

#include "terrain/feature.h"

namespace dt {

BaseGround BaseGroundFromTerrain(const Terrain& terrain) {
  BaseGround base{terrain.ground(), {}};
  uint32_t number = 0;
  for (const Feature* f : terrain.FeaturesById()) {
    if (f->type() == FeatureType::kEarthMove) continue;  // already in the posts
    base.features.emplace_back(FeatureId{kGroundOrigin.site, kGroundOrigin.host, ++number},
                               f->params());
  }
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
