// FeatureEdit: named parameter values ("radius_m=8") that build a new feature or change one.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/result.h"
#include "terrain/feature_params.h"
#include "terrain/material.h"

namespace dt {

// The keys, in the units their names give (docs/node.md "Feature keys"):
//   every type: x_m, z_m
//   crater:     radius_m
//   berm:       direction_deg (-360 .. 360), length_m, width_m, height_m
//   bridge:     direction_deg, width_m, ramp1_m, span_m, ramp2_m, height1_m, height2_m,
//               status ("intact" = 0 or "destroyed" = 1, as a number)
//   crater also: depth_m (below the ground, default 0)
//   ditch:      side_run_m, spoil_height_m, spoil_width_m, and points
//   berm_line:  points
//   area:       level_m (water only), points, and the soil (FeatureEdit::soil)
// Points are keyed points[i].x_m, points[i].z_m, points[i].height_m, points[i].width_m (a ditch's
// height_m is its depth); an index one past the last point appends a point, so a line grows by
// naming its next point. The types with points have no x_m, z_m keys: they stand at points[0].
struct FeatureEdit {
  std::vector<std::pair<std::string, double>> values;  // in the order given
  std::optional<Material> soil;                        // an area's soil (water: flooded)
};

// The keys a type accepts, and the ones a new feature of that type must give.
std::vector<std::string_view> FeatureKeys(FeatureType type);
std::vector<std::string_view> RequiredFeatureKeys(FeatureType type);

// Applies every value to a copy of `params` and validates the result (ValidateFeatureParams).
// An unknown key for the type, a non-finite value or an invalid result is an Error naming the
// key and value; `params` is never half-changed.
Result<FeatureParams> ApplyFeatureEdit(const FeatureParams& params, const FeatureEdit& edit);

// A new feature of `type` from the edit; every required key must be present.
Result<FeatureParams> MakeFeature(FeatureType type, const FeatureEdit& edit);

// "crater" / "berm" / "bridge" / "ditch" / "berm_line" / "area".
Result<FeatureType> ParseFeatureType(std::string_view name);

}  // namespace dt
