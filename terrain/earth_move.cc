#include "terrain/earth_move.h"

#include <algorithm>

#include <fmt/format.h>

namespace dt {

Result<std::unique_ptr<Feature>> MakeEarthMove(FeatureId id, const FeatureParams& params,
                                               const HeightGrid& ground) {
  if (auto m = CheckPlacementBasics(id, params, FeatureType::kEarthMove, ground); !m) {
    return m.error();
  }
  const int nx = ground.posts_x(), nz = ground.posts_z();
  int min_i = nx, min_j = nz, max_i = 0, max_j = 0;
  for (size_t k = 0; k < params.post_deltas.size(); ++k) {
    const PostDelta& d = params.post_deltas[k];
    if (d.i >= nx || d.j >= nz) {
      return Error{
          fmt::format("earth_move {}: post_deltas[{}] post ({}, {}) is outside the {} x {} "
                      "grid",
                      id.ToString(), k, d.i, d.j, nx, nz)};
    }
    min_i = std::min<int>(min_i, d.i);
    min_j = std::min<int>(min_j, d.j);
    max_i = std::max<int>(max_i, d.i);
    max_j = std::max<int>(max_j, d.j);
  }
  const double s = ground.spacing_m();
  const Rect bounds{min_i * s, min_j * s, max_i * s, max_j * s};
  return std::unique_ptr<Feature>(std::make_unique<EarthMoveFeature>(id, params, bounds));
}

}  // namespace dt
