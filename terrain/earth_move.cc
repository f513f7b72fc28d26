#include "terrain/earth_move.h"

#include <algorithm>

#include <fmt/format.h>

namespace dt {

Result<std::unique_ptr<Feature>> MakeEarthMove(FeatureId id, const FeatureParams& params,
                                               const HeightGrid& ground) {
  if (auto m = CheckPlacementBasics(id, params, FeatureType::kEarthMove, ground); !m) {
    return m.error();
  }
  const int n = ground.posts_per_side();
  int min_i = n, min_j = n, max_i = 0, max_j = 0;
  for (size_t k = 0; k < params.post_deltas.size(); ++k) {
    const PostDelta& d = params.post_deltas[k];
    if (d.i >= n || d.j >= n) {
      return Error{
          fmt::format("earth_move {}: post_deltas[{}] post ({}, {}) is outside the {} x {} "
                      "grid",
                      id.ToString(), k, d.i, d.j, n, n)};
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
