#include "terrain/area_feature.h"

#include <algorithm>

#include <fmt/format.h>

namespace dt {

AreaFeature::AreaFeature(FeatureId id, FeatureParams params)
    : Feature(id), params_(std::move(params)) {
  const auto& pts = params_.points;
  bounds_ = {pts[0].x_m, pts[0].z_m, pts[0].x_m, pts[0].z_m};
  for (const FeaturePoint& q : pts) bounds_ = bounds_.Union({q.x_m, q.z_m, q.x_m, q.z_m});
}

bool AreaFeature::Inside(double x_m, double z_m) const {
  if (!bounds_.Contains(x_m, z_m)) return false;  // also refuses NaN
  // Even-odd crossing test along +x; an edge counts for z in [z_lo, z_hi), so a vertex on the
  // ray is counted once.
  bool inside = false;
  const auto& pts = params_.points;
  for (size_t i = 0, k = pts.size() - 1; i < pts.size(); k = i++) {
    const FeaturePoint& a = pts[i];
    const FeaturePoint& b = pts[k];
    if ((a.z_m > z_m) == (b.z_m > z_m)) continue;
    const double x_cross = a.x_m + (z_m - a.z_m) * (b.x_m - a.x_m) / (b.z_m - a.z_m);
    if (x_m < x_cross) inside = !inside;
  }
  return inside;
}

bool AreaFeature::MayCover(const Rect& rect) const {
  if (!bounds_.Intersects(rect)) return false;
  // The rectangle meets the polygon if a corner is inside it, a polygon point is inside the
  // rectangle, or an edge crosses the rectangle (tested conservatively by the edge's own box).
  if (Inside(rect.min_x, rect.min_z) || Inside(rect.max_x, rect.max_z) ||
      Inside(rect.min_x, rect.max_z) || Inside(rect.max_x, rect.min_z)) {
    return true;
  }
  const auto& pts = params_.points;
  for (size_t i = 0, k = pts.size() - 1; i < pts.size(); k = i++) {
    const Rect edge{std::min(pts[i].x_m, pts[k].x_m), std::min(pts[i].z_m, pts[k].z_m),
                    std::max(pts[i].x_m, pts[k].x_m), std::max(pts[i].z_m, pts[k].z_m)};
    if (edge.Intersects(rect)) return true;
  }
  return false;
}

int AreaFeature::precedence() const {
  switch (params_.material) {
    case Material::kWater:
      return 4;
    case Material::kOil:
      return 3;
    case Material::kMud:
      return 2;
    case Material::kBurnt:
      return 1;
    default:
      return 0;
  }
}

Result<std::unique_ptr<Feature>> MakeAreaFeature(FeatureId id, const FeatureParams& params,
                                                 const HeightGrid& ground) {
  Result<Material> resolved = CheckPlacementBasics(id, params, FeatureType::kArea, ground);
  if (!resolved) return resolved.error();
  return std::unique_ptr<Feature>(new AreaFeature(id, params));
}

}  // namespace dt
