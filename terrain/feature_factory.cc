// MakeFeature: validates parameters and dispatches to the feature classes.
#include <fmt/format.h>

#include "base/demand.h"
#include "terrain/area_feature.h"
#include "terrain/berm.h"
#include "terrain/bridge.h"
#include "terrain/crater.h"
#include "terrain/earth_move.h"
#include "terrain/feature.h"
#include "terrain/polyline_earthwork.h"

namespace dt {

Result<std::unique_ptr<Feature>> MakeFeature(FeatureId id, const FeatureParams& params,
                                             const HeightGrid& ground) {
  if (id.number == 0) {
    return Error{fmt::format("feature {} has number 0, which means 'no feature'", id.ToString())};
  }
  // Each maker validates the parameters and the placement point first (CheckPlacementBasics):
  // checked here as well, they were checked twice for every feature added.
  switch (params.type) {
    case FeatureType::kCrater:
      return MakeCrater(id, params, ground);
    case FeatureType::kBerm:
      return MakeBerm(id, params, ground);
    case FeatureType::kBridge:
      return MakeBridge(id, params, ground);
    case FeatureType::kDitch:
    case FeatureType::kBermLine:
      return MakePolylineEarthwork(id, params, ground);
    case FeatureType::kArea:
      return MakeAreaFeature(id, params, ground);
    case FeatureType::kEarthMove:
      return MakeEarthMove(id, params, ground);
  }
  // Not a feature type: ValidateFeatureParams says so.
  if (auto s = ValidateFeatureParams(params); !s) {
    return Error{fmt::format("feature {}: {}", id.ToString(), s.error().message)};
  }
  DT_UNREACHABLE();  // ValidateFeatureParams refuses an unknown type
}

Result<Material> CheckPlacementBasics(FeatureId id, const FeatureParams& params,
                                      FeatureType expected, const HeightGrid& ground) {
  if (params.type != expected) {
    return Error{fmt::format("feature {}: a {} maker given a {}", id.ToString(),
                             FeatureTypeName(expected), FeatureTypeName(params.type))};
  }
  if (auto s = ValidateFeatureParams(params); !s) {
    return Error{
        fmt::format("{} {}: {}", FeatureTypeName(expected), id.ToString(), s.error().message)};
  }
  if (!ground.Contains(params.x_m, params.z_m)) {
    return Error{
        fmt::format("{} {}: placement point (x {}, z {}) m is off the terrain [0, {}] x [0, {}] m",
                    FeatureTypeName(expected), id.ToString(), params.x_m, params.z_m,
                    ground.size_x_m(), ground.size_z_m())};
  }
  if (params.material != Material::kFromGround) return params.material;
  return ground.soil(ground.SquareAt(params.x_m, params.z_m),
                     ground.HalfAt(params.x_m, params.z_m));
}

}  // namespace dt
