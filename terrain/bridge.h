// Bridge: an overpass of two ramps and a span with hot spots at its ends (thesis IV).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "terrain/feature.h"

namespace dt {

// Length along the bridge of each hot spot, centred where a ramp meets the ground: twice the
// longest built-in vehicle (tank, 7.9 m), rounded (docs/terrain.md "Bridges").
inline constexpr double kBridgeHotSpotLengthM = 16.0;

// Which hot spot. Hot spot 1 is at the foot of ramp 1, hot spot 2 at the foot of ramp 2.
enum class BridgeHotSpot : uint8_t { kNone = 0, kRamp1 = 1, kRamp2 = 2 };

// A point in the bridge's frame: metres along the direction from the joint of ramp 1 and the
// span, and metres to the right of the centre line.
struct BridgeCoords {
  double along_m = 0.0;
  double right_m = 0.0;
};

// One cross-section of the deck: both points of a cross pair stand at the same elevation.
struct DeckSection {
  double along_m = 0.0;
  double elevation_m = 0.0;
};

// Along the direction: ramp 1 from -ramp1 to 0, span from 0 to span, ramp 2 from span to
// span + ramp2. The deck elevation depends only on the along coordinate: linear from the ground
// at the foot of ramp 1 to height1 above the ground at the first joint, to height2 above the
// ground at the second joint, to the ground at the foot of ramp 2. The ground at those four
// points (and the span's middle) is cached and refreshed in OnGroundChanged.
//
// A bridge is not an earthwork: OffsetAboveGround is always nullopt and vehicles reach the deck
// through bridge_traversal.h. A destroyed bridge's span is broken: its middle lies on the ground
// (DeckProfile) and it carries no vehicle (DeckElevationAt is nullopt over it); the ramps still do.
class Bridge final : public Feature {
 public:
  FeatureType type() const override { return FeatureType::kBridge; }
  FeatureParams params() const override { return params_; }
  Material material() const override { return resolved_material_; }

  // Covers the deck and both hot spots.
  Rect Bounds() const override;
  // Over the deck (ramps and span), whatever the status.
  bool Covers(double x_m, double z_m) const override;
  bool MayCover(const Rect& rect) const override;
  double OffsetOrNotCovered(double, double) const override { return kNotCovered; }
  void OnGroundChanged(const HeightGrid& ground) override;
  // Another bridge whose deck overlaps this deck (touching edges do not count).
  bool ConflictsWith(const Feature& other) const override;
  bool CanConflict() const override { return true; }

  double direction_rad() const { return params_.direction_rad; }
  double width_m() const { return params_.width_m; }
  double span_length_m() const { return params_.length_m[0]; }
  double ramp1_length_m() const { return params_.length_m[1]; }
  double ramp2_length_m() const { return params_.length_m[2]; }
  bool destroyed() const { return params_.status == BridgeStatus::kDestroyed; }
  // Along coordinates of the two ramp feet.
  double start_along_m() const { return -ramp1_length_m(); }
  double end_along_m() const { return span_length_m() + ramp2_length_m(); }

  BridgeCoords ToBridge(double x_m, double z_m) const;
  // True if the point is over the deck's plan: ramps and span, edges included.
  bool OverDeck(double x_m, double z_m) const;
  // The deck elevation at a point over a drivable part of the deck; nullopt elsewhere (off the
  // deck, or over a destroyed span).
  std::optional<double> DeckElevationAt(double x_m, double z_m) const;

  // The hot spot holding the point (as wide as the deck, kBridgeHotSpotLengthM long, centred on
  // a ramp foot), or kNone. Where the two overlap (very short bridges) hot spot 1 wins.
  BridgeHotSpot HotSpotAt(double x_m, double z_m) const;
  // True in the part of a hot spot beyond its ramp foot, where vehicles leave the bridge.
  bool InOuterHotSpot(double x_m, double z_m) const;
  // The direction a vehicle moves in to get onto the bridge from a hot spot (the bridge
  // direction at ramp 1, its opposite at ramp 2). Throws std::invalid_argument for kNone.
  double OntoDirectionRad(BridgeHotSpot spot) const;

  // The deck's cross-sections from ramp 1's foot to ramp 2's foot, for display and digests:
  // 4 when intact; 6 when destroyed (two extra cross pairs where the broken halves of the span
  // meet the ground at its middle).
  std::vector<DeckSection> DeckProfile() const;
  // Corners (x, z) of the deck's plan, counter-clockwise from ramp 1's foot on the right side.
  std::array<Eigen::Vector2d, 4> DeckCorners() const;

 private:
  Bridge(FeatureId id, const FeatureParams& params, Material resolved);
  // Deck elevation at an along coordinate on [start, end], ignoring the status.
  double IntactDeckAt(double along_m) const;
  Eigen::Vector2d AtBridge(double along_m, double right_m) const;

  FeatureParams params_;
  Material resolved_material_;
  double ux_, uz_;  // unit vector along the bridge
  // Cached ground at the foot of ramp 1, joint 1, joint 2, the foot of ramp 2, the span middle.
  double ground_foot1_m_ = 0, ground_joint1_m_ = 0, ground_joint2_m_ = 0, ground_foot2_m_ = 0,
         ground_middle_m_ = 0;

  friend Result<std::unique_ptr<Feature>> MakeBridge(FeatureId, const FeatureParams&,
                                                     const HeightGrid&);
};

// Builds a bridge. Refuses what ValidateFeatureParams refuses, a type other than bridge, and a
// bridge whose deck or hot spots leave the ground.
Result<std::unique_ptr<Feature>> MakeBridge(FeatureId id, const FeatureParams& params,
                                            const HeightGrid& ground);

}  // namespace dt
