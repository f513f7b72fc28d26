// NodeActions: what scenarios and control commands may ask of a running node.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "base/feature_id.h"
#include "base/result.h"
#include "terrain/feature_params.h"

namespace dt {

// What a drive command set: the vehicle clamps the commanded values to its type's limits
// (vehicle/vehicle.h), so these may differ from what was asked.
struct AppliedDrive {
  std::string vehicle_type;  // "tank"
  double speed_mps = 0.0;
  double heading_rate_rad_s = 0.0;
};

// A vehicle to add at run time (docs/node.md "Control socket": spawn).
struct SpawnRequest {
  std::string type = "tank";  // a built-in type
  double x_m = 0.0, z_m = 0.0, heading_rad = 0.0;
  std::string model = "physical";  // "physical" or "light"
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
  // Adds a vehicle (shared with the exercise); answers its index. Processes without vehicles
  // refuse.
  virtual Result<int> Spawn(const SpawnRequest& request) {
    return Error{fmt::format("cannot spawn a {}: this process has no vehicles", request.type)};
  }
  // Lowers vehicle `index`'s blade to cut depth_m below its tracks, or raises it (nullopt: the
  // load is set down). Refused for a vehicle without a blade or a depth outside the blade's.
  virtual Status SetBlade(int index, std::optional<double> depth_m) {
    (void)depth_m;
    return Error{fmt::format("vehicle {} has no blade: this process has no vehicles", index)};
  }
  // Removes vehicle `index` from the exercise; later vehicles move down one index.
  virtual Status Remove(int index) {
    return Error{fmt::format("cannot remove vehicle {}: this process has no vehicles", index)};
  }
};

}  // namespace dt
