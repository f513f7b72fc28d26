// VehicleSharing: a node's part in shared vehicles: it sends its own vehicles' states under dead
// reckoning and holds every other node's (docs/vehicles.md "Shared vehicles").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pdu/vehicle_state.h"
#include "render/vehicle_sprite.h"
#include "terrain/terrain.h"
#include "transport/pdu_bus.h"
#include "vehicle/dead_reckoning.h"
#include "vehicle/dead_reckoning_policy.h"
#include "vehicle/remote_vehicles.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// The colour a node's vehicles are drawn in, on every node: one of eight by its address.
Rgba OwnerColour(NodeAddress owner);

class VehicleSharing {
 public:
  // Subscribes to VehicleState PDUs on `bus` (which must outlive this).
  VehicleSharing(PduBus& bus, NodeAddress local, DeadReckoningThresholds thresholds);

  // A local vehicle appended to the node's list: it gets the next entity number.
  EntityId AddLocal(const SimulatedVehicle& vehicle);
  // Local vehicle `index` leaves the exercise: its removal is sent (the deactivated bit) and it
  // is forgotten; the caller erases it from its list too.
  void RemoveLocal(size_t index, const SimulatedVehicle& vehicle, double now_s);

  // After the local vehicles advanced to now_s: sends the states that are due, then dead
  // reckons and settles the remote vehicles on `terrain` (dropping silent ones).
  void Tick(const std::vector<SimulatedVehicle>& local, const Terrain& terrain, double now_s);

  // `dt_ctl vehicles`: one line per local vehicle, then one per remote vehicle (docs/node.md).
  std::string VehiclesText(const std::vector<SimulatedVehicle>& local) const;
  // Lines appended to `status`.
  std::string StatusLines() const;
  // The local vehicles and the remote ones, each in its owner's colour.
  std::vector<VehicleSprite> Sprites(const std::vector<SimulatedVehicle>& local) const;

  const RemoteVehicles& remote() const { return remote_; }
  uint64_t sent() const { return sent_; }
  const EntityId& local_id(size_t index) const { return owned_[index].id; }

 private:
  struct Owned {
    EntityId id;
    MotionEstimator motion;
    DeadReckoningOwner owner;
    VehicleStateFields last_truth;
    bool shared = true;   // false for a type with no entity type (never sent)
    EntityType type;      // its type's, when shared
    std::string marking;  // "<type>-<entity number>"
  };
  VehicleStateFields Truth(const Owned& o, const SimulatedVehicle& v, const VehiclePose& p) const;
  void Send(Owned& o, const VehicleStateFields& state, double now_s);

  PduBus& bus_;
  NodeAddress local_;
  DeadReckoningThresholds thresholds_;
  RemoteVehicles remote_;
  std::vector<Owned> owned_;
  uint32_t next_entity_ = 1;
  double now_s_ = 0.0;
  uint64_t sent_ = 0, send_failures_ = 0;
};

}  // namespace dt
