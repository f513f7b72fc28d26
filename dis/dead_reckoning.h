// DIS dead reckoning: where an Entity State puts its entity some time after it was sent, and
// whether a sender's true state has drifted far enough from that for a new Entity State.
#pragma once

#include <numbers>

#include "dis/dis_pdu.h"

namespace dt::dis {

// The usual DIS defaults: 1 m, 3 degrees, a heartbeat every 5 s, an entity dropped after 2.4
// heartbeats without an update.
struct DeadReckoningThresholds {
  double position_m = 1.0;
  double orientation_rad = 3.0 * std::numbers::pi / 180.0;
  double heartbeat_s = 5.0;
  double timeout_heartbeats = 2.4;
};

// Location dt_s seconds after the PDU: static (0, 1) stays; FPW and RPW (2, 3) add V dt; RVW and
// FVW (4, 5) add V dt + A dt^2 / 2. The body-coordinate algorithms (6-9) are not extrapolated
// here: the entity stays at its last location until the next update.
WorldCoordinates ExtrapolatedLocation(const EntityStatePdu& pdu, double dt_s);

// Orientation dt_s seconds after the PDU: the rotating algorithms (RPW 3, RVW 4) turn the body
// by its angular velocity (body axes) times dt; the others keep the orientation.
EulerAngles ExtrapolatedOrientation(const EntityStatePdu& pdu, double dt_s);

// The rotation angle between two orientations, radians in [0, pi].
double OrientationDifferenceRad(const EulerAngles& a, const EulerAngles& b);

enum class UpdateReason : uint8_t {
  kNone = 0,
  kPosition,     // the dead-reckoned location is more than the threshold off
  kOrientation,  // the dead-reckoned orientation is more than the threshold off
  kHeartbeat,    // nothing drifted, but the heartbeat is due
  kChange,       // a field dead reckoning does not predict changed (algorithm, appearance, ...)
};

// Whether `current`, the sender's true state now, needs a new Entity State when `last_sent` went
// out seconds_since_sent ago.
UpdateReason UpdateDue(const EntityStatePdu& last_sent, double seconds_since_sent,
                       const EntityStatePdu& current, const DeadReckoningThresholds& thresholds);

// A receiver drops an entity not updated for timeout_heartbeats heartbeats.
inline bool TimedOut(double seconds_since_received, const DeadReckoningThresholds& t) {
  return seconds_since_received > t.heartbeat_s * t.timeout_heartbeats;
}

}  // namespace dt::dis
