// RemoteVehicles: the vehicles other nodes own, as this node sees them: received states, dead
// reckoned every tick and settled on this node's terrain (docs/vehicles.md "Shared vehicles").
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "base/feature_id.h"
#include "pdu/vehicle_state.h"
#include "terrain/terrain.h"
#include "vehicle/dead_reckoning.h"
#include "vehicle/dead_reckoning_policy.h"
#include "vehicle/vehicle_type.h"

namespace dt {

struct RemoteVehicle {
  EntityId id;
  NodeAddress owner;             // the sender of its states
  VehicleStateFields state;      // the last state received
  Eigen::Matrix3d orientation0;  // OrientationMatrix of `state`, made once for every Tick
  double received_s = 0.0;       // when, on this node's clock
  VehicleType type;              // the built-in type its entity type names
  DrPose pose;                   // dead reckoned to the last Tick and settled on the local terrain
  bool settled = false;          // y, pitch and roll of `pose` come from the local terrain
  double correction_m = 0.0;     // how far the dead-reckoned copy was off when the last state came
  uint64_t updates = 0;
};

// What Apply did with a state.
enum class RemoteApply : uint8_t {
  kAdded,     // a vehicle not held before
  kUpdated,   // a newer state of a held vehicle
  kRemoved,   // its owner removed it (appearance deactivated)
  kConflict,  // its entity ID is held for another sender: dropped
  kIgnored,   // a removal of a vehicle not held
};

class RemoteVehicles {
 public:
  explicit RemoteVehicles(DeadReckoningThresholds thresholds) : thresholds_(thresholds) {}

  // A validated state from `sender`, received at now_s. The entity's first sender holds its ID
  // until it is removed or times out; a state of the same ID from anyone else is dropped, counted
  // and logged (rate-limited).
  RemoteApply Apply(NodeAddress sender, const VehicleStateFields& state, double now_s);
  // Dead reckons every vehicle to now_s and settles ground vehicles on `terrain`; drops (with a
  // log line each) the vehicles not heard for the timeout. Returns the IDs dropped.
  std::vector<EntityId> Tick(const Terrain& terrain, double now_s);

  const std::map<EntityId, RemoteVehicle>& vehicles() const { return vehicles_; }
  size_t count_owned_by(NodeAddress owner) const;
  uint64_t conflicts() const { return conflicts_; }
  uint64_t timed_out() const { return timed_out_; }
  uint64_t removed() const { return removed_; }
  uint64_t received() const { return received_; }
  const DeadReckoningThresholds& thresholds() const { return thresholds_; }

 private:
  DeadReckoningThresholds thresholds_;
  std::map<EntityId, RemoteVehicle> vehicles_;
  uint64_t conflicts_ = 0, timed_out_ = 0, removed_ = 0, received_ = 0;
  double last_conflict_log_s_ = -1e300;
  uint64_t conflicts_unlogged_ = 0;
};

// How far above the owner's elevation a bridge solid's top may be and still carry a remote
// vehicle (SettleOnTerrain); a higher one is passed under.
inline constexpr double kRemoteClimbM = 1.0;
// How densely SettleOnTerrain samples a footprint near an earthwork or a bridge.
inline constexpr double kRemoteSettleStepM = 0.5;

// Settles a vehicle of `type` at pose.location (x, z) and heading on `terrain`'s surface: the
// ground with its earthworks and, within kRemoteClimbM above the owner's elevation
// (pose.location y), the tops of this node's bridge solids. Pitch and roll are the slopes between
// the surface under the centres of opposite sides; y is the mean of the four, and near an
// earthwork or a bridge lays that plane on the highest point of the surface under the footprint
// (sampled every kRemoteSettleStepM), so the footprint is not below the surface (docs/vehicles.md
// "Shared vehicles"). Returns false, leaving the pose alone, where the footprint is not on the
// terrain.
bool SettleOnTerrain(const Terrain& terrain, const VehicleType& type, DrPose& pose);

}  // namespace dt
