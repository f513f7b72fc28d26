// Bridge solids: the deck slabs, piers and fallen-span rubble a physical vehicle meets.
#pragma once

#include <vector>

#include "base/feature_id.h"
#include "terrain/bridge.h"
#include "terrain/material.h"
#include "terrain/terrain.h"

namespace dt {

// Thickness of every deck slab (ramps and span): its underside is this far below the deck.
inline constexpr double kDeckThicknessM = 0.5;
// Piers: a square column this wide under each deck edge at each joint of ramp and span.
inline constexpr double kPierWidthM = 1.0;
// A destroyed span lies on the ground under it as rubble this high (lower on a low bridge).
inline constexpr double kRubbleHeightM = 1.0;

// A solid of a bridge: in the bridge's frame (bridge.h BridgeCoords) it covers `along` in
// [a0_m, a1_m] and `right` in [r0_m, r1_m]; at each point its bottom and top are linear in
// `along` (bottom0/top0 at a0, bottom1/top1 at a1). Its top carries vehicles; its sides and
// bottom stop them.
struct Solid {
  FeatureId bridge;
  Material material = Material::kConcrete;
  bool deck = false;                          // a deck slab: standing on it is being on the bridge
  bool rubble = false;                        // a destroyed span lying on the ground
  double origin_x_m = 0.0, origin_z_m = 0.0;  // the bridge's placement point
  double ux = 1.0, uz = 0.0;                  // unit vector along the bridge
  double a0_m = 0.0, a1_m = 0.0, r0_m = 0.0, r1_m = 0.0;
  double bottom0_m = 0.0, bottom1_m = 0.0, top0_m = 0.0, top1_m = 0.0;

  // Bridge-frame coordinates of a ground point.
  void ToLocal(double x_m, double z_m, double& along_m, double& right_m) const {
    const double dx = x_m - origin_x_m, dz = z_m - origin_z_m;
    along_m = dx * ux + dz * uz;
    right_m = dx * uz - dz * ux;
  }
  bool InPlan(double along_m, double right_m) const {
    return along_m >= a0_m && along_m <= a1_m && right_m >= r0_m && right_m <= r1_m;
  }
  double TopAt(double along_m) const { return top0_m + (along_m - a0_m) * TopSlope(); }
  double BottomAt(double along_m) const {
    return bottom0_m + (along_m - a0_m) * (bottom1_m - bottom0_m) / (a1_m - a0_m);
  }
  double TopSlope() const { return (top1_m - top0_m) / (a1_m - a0_m); }
};

// The rectangle on the ground holding a solid's plan.
Rect PlanBounds(const Solid& solid);

// The plans of a bridge's solids (kinds, origin, direction and a0/a1/r0/r1; no heights, bridge ID
// or material) from its parameters alone, in the order BridgeSolids gives them: ramp 1, the span
// (intact only), ramp 2, the four piers, the rubble (destroyed only). What a plan view draws.
std::vector<Solid> BridgeSolidPlans(const FeatureParams& bridge);

// The solids of one bridge (docs/vehicles.md "Bridges as solids"): an intact bridge is three
// deck slabs (ramp 1, span, ramp 2) and four piers; a destroyed one keeps its ramp slabs and piers
// and has rubble on the ground instead of a span.
std::vector<Solid> BridgeSolids(const Bridge& bridge, const HeightGrid& ground);

// The solids of every bridge indexed in the grid squares the rectangle touches, by bridge ID.
std::vector<Solid> SolidsNear(const Terrain& terrain, const Rect& area);
// The same into `out` (cleared first), reusing its storage.
void SolidsNear(const Terrain& terrain, const Rect& area, std::vector<Solid>& out);

}  // namespace dt
