// Vehicle traversal: settles a vehicle on the terrain, its earthworks and bridges (thesis III.B,
// IV.B). The terrain stays const; only the vehicle changes.
#pragma once

#include "base/result.h"
#include "terrain/terrain.h"
#include "vehicle/bridge_traversal.h"
#include "vehicle/vehicle.h"
#include "vehicle/vehicle_orientation.h"

namespace dt {

struct TraversalReport {
  OrientationMethod method = OrientationMethod::kTwoPoint;
  BridgeEvent event = BridgeEvent::kNone;
  bool died = false;  // died in this call
  // When event == kFellOff: the tilt of the fall, checked against the type's limits.
  double fall_pitch_rad = 0.0;
  double fall_roll_rad = 0.0;
};

// Updates the vehicle's on-bridge tag, then its orientation and elevation:
//  1. the tag (UpdateBridgeTag) from the bridges near its orientation points;
//  2. on a bridge, if more than one corner is not carried by the deck (UncarriedCorners) or its
//     centre is neither over the deck nor in a hot spot, it falls off: the tilt of the fall is the
//     corner plane with carried corners on the deck and the others on the ground
//     (CornerPlaneTilt); it dies if |pitch| or |roll| exceeds the type's limits; the tag clears;
//  3. two-point orientation when it is on no bridge, no bridge is near, and the feature bitgrid is
//     clear at the centre and all orientation points; six-point otherwise, with elevations from
//     VehicleSurfaceAt and the direction of travel from the sign of the speed.
// A dead vehicle is settled on the ground and earthworks with no tag. Refused, changing nothing,
// when the vehicle was made for another terrain size or a point of its footprint is off the
// terrain.
Result<TraversalReport> SettleVehicle(const Terrain& terrain, Vehicle& vehicle);

// Vehicle::Step then SettleVehicle.
Result<TraversalReport> DriveVehicle(const Terrain& terrain, Vehicle& vehicle, double dt_s);

}  // namespace dt
