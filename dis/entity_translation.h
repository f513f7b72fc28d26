// The gateway's translation of vehicles between the exercise's VehicleState and DIS Entity State
// (docs/dis.md "The gateway"): appearance bits, dead-reckoning algorithms, entity types, markings.
#pragma once

#include <cstdint>

#include "base/result.h"
#include "dis/dis_pdu.h"
#include "dis/geodetic_frame.h"
#include "dis/pdu_context.h"
#include "pdu/vehicle_state.h"

namespace dt::dis {

// A vehicle of the exercise as an Entity State. The exercise's own appearance bits (on a bridge,
// falling: bits 28, 29) are cleared; every other field maps one to one. Fails (ToEntityState)
// for a value that is not finite or does not fit the PDU's floats.
Result<EntityStatePdu> EntityStateOfVehicle(const VehicleStateFields& state,
                                            const GeodeticFrame& frame, const PduContext& context);
// The same with TrigOf the state's heading, pitch and roll given.
Result<EntityStatePdu> EntityStateOfVehicle(const VehicleStateFields& state,
                                            const AttitudeTrig& trig, const GeodeticFrame& frame,
                                            const PduContext& context);

// What an outside Entity State becomes on the exercise bus. terrain_size_x_m bounds x,
// terrain_size_z_m bounds z.
// Fails, naming the values, for an entity off the terrain, an entity type that is no land
// platform (kind 1, domain 1), or a reserved entity number. Mapped, documented in docs/dis.md:
// land platforms of category 1 are tanks, category 6 jeeps, any other truck (an exact built-in
// type keeps its own); the body-axis dead-reckoning algorithms (6..9) become their world-axis
// counterparts (2..5) and 0 (other) becomes FPW; force IDs above 3 become 0 (other); appearance
// keeps the damage, mobility-kill and deactivated bits only; marking characters outside
// printable ASCII end the marking.
Result<VehicleStateFields> VehicleOfEntityState(const EntityStatePdu& pdu,
                                                const GeodeticFrame& frame, double terrain_size_x_m,
                                                double terrain_size_z_m);

}  // namespace dt::dis
