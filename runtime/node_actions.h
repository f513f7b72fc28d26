// NodeActions: what scenarios and control commands may ask of a running node.
#pragma once

#include <optional>
#include <vector>

#include "terrain/feature_id.h"
#include "terrain/feature_params.h"
#include "terrain/result.h"

namespace dt {

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
  // Commands vehicle `index` (0-based).
  virtual Status Drive(int index, double speed_mps, double heading_rate_rad_s) = 0;
};

}  // namespace dt
