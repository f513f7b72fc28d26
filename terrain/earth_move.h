// EarthMoveFeature: blade work kept as a feature, so it is logged, sent and saved like the others.
#pragma once

#include <memory>

#include "terrain/feature.h"

namespace dt {

// An earth move changes grid posts by whole millimetres (FeatureParams::post_deltas). It has no
// offset above the ground and covers no point: Terrain adds its deltas to the ground posts when
// it is added and takes them off when it is removed (docs/terrain.md "Blade work"), so it is
// never listed in the terrain's squares.
class EarthMoveFeature final : public Feature {
 public:
  EarthMoveFeature(FeatureId id, FeatureParams params, Rect bounds)
      : Feature(id), params_(std::move(params)), bounds_(bounds) {}

  FeatureType type() const override { return FeatureType::kEarthMove; }
  FeatureParams params() const override { return params_; }
  const std::vector<PostDelta>& post_deltas() const { return params_.post_deltas; }
  // Moved soil has no material of its own: the ground's soil stays.
  Material material() const override { return Material::kDirt; }
  Rect Bounds() const override { return bounds_; }
  bool Covers(double, double) const override { return false; }
  bool MayCover(const Rect&) const override { return false; }
  double OffsetOrNotCovered(double, double) const override { return kNotCovered; }

 private:
  FeatureParams params_;
  Rect bounds_;
};

// Validates the parameters and checks that every post lies on the grid; the error names the
// first post outside it.
Result<std::unique_ptr<Feature>> MakeEarthMove(FeatureId id, const FeatureParams& params,
                                               const HeightGrid& ground);

}  // namespace dt
