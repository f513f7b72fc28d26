// Bridge traversal: the on-bridge tag rules and the elevation a vehicle sees near bridges
// (thesis IV.B).
#pragma once

#include <cstdint>
#include <numbers>
#include <span>

#include "terrain/bridge.h"
#include "terrain/terrain.h"
#include "vehicle/vehicle.h"

namespace dt {

// A vehicle's direction of travel must be within this of the bridge's to get on or off it.
inline constexpr double kBridgeAlignToleranceRad = 20.0 * std::numbers::pi / 180.0;

enum class BridgeEvent : uint8_t {
  kNone = 0,
  kMounted = 1,   // the tag was set: the vehicle is on a deck from now on
  kDroveOff = 2,  // the tag was cleared in the outer part of a hot spot, headed off
  kFellOff = 3,   // the tag was cleared because the deck no longer carries the vehicle
};

// True if the vehicle moves (speed != 0) in a direction within kBridgeAlignToleranceRad of
// `direction_rad`. A vehicle at rest never gets on or off.
bool MovingAlong(const Vehicle& vehicle, double direction_rad);

// Gets the vehicle off its bridge when its centre is in the outer part of a hot spot and it
// moves off the bridge; then, if it is on no bridge, gets it on the first bridge (by ID) in whose
// hot spot its centre is and onto whose deck it moves. Backing on and off works: the direction of
// travel counts, not the heading. `nearby` holds the bridges to consider, sorted by ID.
BridgeEvent UpdateBridgeTag(std::span<const Bridge* const> nearby, Vehicle& vehicle);

// The elevation under one orientation point. On a bridge (`on` not null): the deck where the
// deck carries vehicles, elsewhere Terrain::ElevationAt. On no bridge: Terrain::ElevationAt, raised
// to the deck of any bridge whose hot spot holds the point, so ramp ends are crossed like berms
// while the rest of a deck is passed under.
double VehicleSurfaceAt(const Terrain& terrain, std::span<const Bridge* const> nearby,
                        const Bridge* on, GroundPoint p);

// How many of the vehicle's four corners (tires) the bridge does not carry: corners alongside
// the raised deck (between the ramp feet) but not over its drivable part, i.e. off a side or over
// a destroyed span. Beyond a ramp foot the deck meets the ground, so corners there are carried.
int UncarriedCorners(const Bridge& bridge, const Vehicle& vehicle);

}  // namespace dt
