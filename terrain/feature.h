// Feature: the base class of every dynamic terrain feature (crater, berm, bridge).
#pragma once

#include <limits>
#include <memory>
#include <optional>

#include "base/feature_id.h"
#include "base/rect.h"
#include "base/result.h"
#include "terrain/feature_params.h"
#include "terrain/height_grid.h"
#include "terrain/material.h"

namespace dt {

// A feature is defined by its FeatureParams and the bare ground (thesis `nodef_elev`): its
// geometry never depends on other features, so the terrain's state is independent of the order
// features were added. Earthworks (craters, berms) are draped on the ground: each mesh vertex has
// an offset above the bare ground, and between vertices the surface keeps the interpolated offset
// above the ground (docs/terrain.md). Bridges stand on their own deck geometry (bridge.h).
class Feature {
 public:
  virtual ~Feature() = default;
  Feature(const Feature&) = delete;
  Feature& operator=(const Feature&) = delete;

  FeatureId id() const { return id_; }
  virtual FeatureType type() const = 0;
  // The parameters that rebuild this feature exactly: MakeFeature(id(), params(), ground).
  virtual FeatureParams params() const = 0;
  // The resolved material (never kFromGround).
  virtual Material material() const = 0;

  // Axis-aligned bounds of everything the feature covers.
  virtual Rect Bounds() const = 0;
  // True if the feature covers the ground point (x, z).
  virtual bool Covers(double x_m, double z_m) const = 0;
  // True if the feature may cover any point of the rectangle (conservative: used for the
  // feature-presence bitgrid). The default uses Bounds().
  virtual bool MayCover(const Rect& rect) const { return Bounds().Intersects(rect); }

  // Earthworks: height of the surface above the bare ground at (x, z), or nullopt where the
  // feature does not cover the point. Bridges return nullopt: vehicles reach decks through
  // the bridge's own interface.
  std::optional<double> OffsetAboveGround(double x_m, double z_m) const {
    const double offset_m = OffsetOrNotCovered(x_m, z_m);
    if (offset_m == kNotCovered) return std::nullopt;
    return offset_m;
  }
  // The same, with kNotCovered (-inf) for "not covered". The elevation query's inner loop
  // calls this: a virtual returning std::optional<double> goes through memory and stalls on
  // store forwarding, which made a four-crater query cost ~5x a bare one.
  static constexpr double kNotCovered = -std::numeric_limits<double>::infinity();
  virtual double OffsetOrNotCovered(double x_m, double z_m) const = 0;

  // Called after a post under the feature changed, for features that cache ground elevations.
  virtual void OnGroundChanged(const HeightGrid& /*ground*/) {}
  // True if this feature may not coexist with `other` (bridges may not overlap). Only ever true
  // between two features that both CanConflict(), so placing the others checks nothing.
  virtual bool ConflictsWith(const Feature& /*other*/) const { return false; }
  virtual bool CanConflict() const { return false; }

 protected:
  explicit Feature(FeatureId id) : id_(id) {}

 private:
  FeatureId id_;
};

// Validates the parameters, checks that the feature lies on the terrain, and builds it on the
// bare ground. The error names the offending values.
Result<std::unique_ptr<Feature>> MakeFeature(FeatureId id, const FeatureParams& params,
                                             const HeightGrid& ground);

// What every feature type's maker checks first: `params` is of type `expected`, valid, and its
// placement point lies on the terrain. Returns the resolved material: the soil of the ground
// triangle under the placement point where the parameters say kFromGround.
Result<Material> CheckPlacementBasics(FeatureId id, const FeatureParams& params,
                                      FeatureType expected, const HeightGrid& ground);

}  // namespace dt
