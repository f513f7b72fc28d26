// A vehicle's pose as a DIS Entity State PDU, and an outside Entity State as a pose.
#pragma once

#include "base/result.h"
#include "dis/dis_pdu.h"
#include "dis/geodetic_frame.h"
#include "dis/pdu_context.h"
#include "dis/vehicle_pose.h"

namespace dt::dis {

// Fails, naming the field, for a non-finite value, one too large for the PDU's float, or a
// marking longer than 11 characters or not printable ASCII: the pose comes from a state heard
// on the bus, and a handler drops what it cannot send. A PDU it gives encodes without error.
Result<EntityStatePdu> ToEntityState(const VehiclePose& pose, const GeodeticFrame& frame,
                                     const PduContext& context);
// The same, bit for bit, with the attitude's trigonometry given (TrigOf(pose.attitude)), for a
// caller that needs it again.
Result<EntityStatePdu> ToEntityState(const VehiclePose& pose, const AttitudeTrig& trig,
                                     const GeodeticFrame& frame, const PduContext& context);

// Entity numbers 0 (none), 65534 (assign on request) and 65535 (all) are reserved.
inline constexpr uint16_t kFirstReservedEntityNumber = 65534;

// An Entity State (already decoded, so finite) as a pose. The marking is kept up to its first
// NUL when the character set is ASCII, and left empty otherwise. Fails for a reserved entity
// number, a dead-reckoning algorithm outside SISO-REF-010's 0..9 or a location that does not
// convert to finite local metres.
Result<VehiclePose> FromEntityState(const EntityStatePdu& pdu, const GeodeticFrame& frame);

}  // namespace dt::dis
