// AreaFeature: a polygon of other soil on the ground (flooded, burnt, mud, oil), changing the
// surface's material but not its height; water fills low ground to a level.
#pragma once

#include <memory>
#include <vector>

#include "terrain/feature.h"

namespace dt {

// Built from FeatureParams of type kArea (feature_params.h). Inside is by the even-odd rule, so
// any polygon, even a self-crossing one, has one answer. The area never raises or cuts the
// surface (OffsetOrNotCovered is always kNotCovered); Terrain::SoilAt and Terrain::WaterLevelAt
// ask it through Inside().
class AreaFeature final : public Feature {
 public:
  FeatureType type() const override { return FeatureType::kArea; }
  FeatureParams params() const override { return params_; }
  Material material() const override { return params_.material; }

  Rect Bounds() const override { return bounds_; }
  bool Covers(double x_m, double z_m) const override { return Inside(x_m, z_m); }
  bool MayCover(const Rect& rect) const override;
  double OffsetOrNotCovered(double /*x_m*/, double /*z_m*/) const override { return kNotCovered; }

  bool Inside(double x_m, double z_m) const;
  bool is_water() const { return params_.material == Material::kWater; }
  // The water level (absolute elevation, metres); meaningful only for water.
  double water_level_m() const { return params_.height_m[0]; }
  // Precedence of the area's soil where areas overlap (Terrain::SoilAt): water, then oil, mud,
  // burnt, then any other soil; higher wins.
  int precedence() const;

 private:
  AreaFeature(FeatureId id, FeatureParams params);

  FeatureParams params_;
  Rect bounds_;

  friend Result<std::unique_ptr<Feature>> MakeAreaFeature(FeatureId, const FeatureParams&,
                                                          const HeightGrid&);
};

Result<std::unique_ptr<Feature>> MakeAreaFeature(FeatureId id, const FeatureParams& params,
                                                 const HeightGrid& ground);

}  // namespace dt
