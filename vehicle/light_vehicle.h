// LightVehicle: the thesis's kinematic rules (vehicle/vehicle_traversal.h) as the light model,
// with a fall off a bridge reported once.
#pragma once

#include "base/result.h"
#include "terrain/terrain.h"
#include "vehicle/vehicle.h"
#include "vehicle/vehicle_traversal.h"

namespace dt {

struct LightReport {
  TraversalReport traversal;  // as SettleVehicle gave it
  // The events to report: kFellOff only for the first fall from a bridge, and kMounted not while
  // the vehicle still hangs in the hot spot it fell in (SettleVehicle sets the tag again there
  // every tick and drops it again: the fall would be reported once per tick).
  BridgeEvent event = BridgeEvent::kNone;
  FeatureId bridge;  // the bridge of `event`
};

class LightVehicle {
 public:
  // Vehicle::Make, then settled on the terrain.
  static Result<LightVehicle> Make(const VehicleType& type, const Terrain& terrain, double x_m,
                                   double z_m, double heading_rad);

  Status Command(double speed_mps, double heading_rate_rad_s) {
    return vehicle_.Command(speed_mps, heading_rate_rad_s);
  }
  // DriveVehicle for dt_s, with the events filtered as LightReport says.
  Result<LightReport> Advance(const Terrain& terrain, double dt_s);

  const Vehicle& vehicle() const { return vehicle_; }

 private:
  explicit LightVehicle(Vehicle v) : vehicle_(std::move(v)) {}
  // The first bridge (by ID) whose deck or hot spots hold the vehicle's centre.
  FeatureId BridgeAtCentre(const Terrain& terrain) const;

  Vehicle vehicle_;
  FeatureId fell_from_;  // the fall from this bridge was reported; cleared once clear of it
};

}  // namespace dt
