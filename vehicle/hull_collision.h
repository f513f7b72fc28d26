// Hull collision: how far a vehicle's hull has entered a bridge solid, and which way out.
#pragma once

#include <span>

#include <Eigen/Core>

#include "base/feature_id.h"
#include "vehicle/bridge_solids.h"

namespace dt {

struct HullPenetration {
  bool hit = false;
  Eigen::Vector3d push_m = Eigen::Vector3d::Zero();  // translation that takes the point out
  // The face's outward unit normal: push_m's direction, except down through a sloping underside,
  // where push_m is straight down and the normal leans with the slope.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  // the deepest point (world)
  double depth_m = 0.0;
  FeatureId bridge;
};

// The deepest of the points inside a solid (strictly between its bottom and top, in its plan),
// with the shortest way out: through one of the four sides; up through the top or down through
// the bottom when that is at most `max_vertical_m` (a belly or a roof grazing a slab); or level
// along the bridge, out from under a sloping bottom or off a sloping top (a roof meeting a ramp's
// underside goes back the way the underside rises, not out of the ramp's side).
// With `prefer_top`, a point within max_vertical_m under a top goes up even when a side is
// nearer: a hull whose bottom is roughly level and has come down onto a deck's edge rests on it
// (out through the near side pushed a jeep with its centre over the deck off it).
HullPenetration DeepestPenetration(std::span<const Eigen::Vector3d> points,
                                   std::span<const Solid> solids, double max_vertical_m,
                                   bool prefer_top = false);

}  // namespace dt
