// NodeActions: what scenarios and control commands may ask of a running node.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "terrain/feature_id.h"
#include "terrain/feature_params.h"
#include "terrain/result.h"

namespace dt {

// What a drive command set: the vehicle clamps the commanded values to its type's limits
// (terrain/vehicle.h), so these may differ from what was asked.
struct AppliedDrive {
  std::string vehicle_type;  // "tank"
  double speed_mps = 0.0;
  double heading_rate_rad_s = 0.0;
};

// Implemented by the node process over its replica and vehicles; tests implement it in memory.
// Every call either does all it says or returns an Error and changes nothing.
class NodeActions {
 public:
  virtual ~NodeActions() = default;
  virtual Result<FeatureId> Create(const FeatureParams& params) = 0;
  // The current parameters of a live feature; nullopt if unknown or destroyed.
  virtual std::optional<FeatureParams> Params(FeatureId id) const = 0;
  virtual Status Modify(FeatureId id, const FeatureParams& params) = 0;
  virtual Status Destroy(FeatureId id) = 0;
  virtual Result<std::vector<FeatureId>> Breach(FeatureId berm, double gap_start_m,
                                                double gap_width_m) = 0;
  virtual int vehicle_count() const = 0;
  // Commands vehicle `index` (0-based); answers what the vehicle took after clamping.
  virtual Result<AppliedDrive> Drive(int index, double speed_mps, double heading_rate_rad_s) = 0;
};

}  // namespace dt
