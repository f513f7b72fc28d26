#include "dis/vehicle_mapping.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>

namespace dt::dis {
namespace {

std::optional<Error> NonFinite(double v, const char* field) {
  if (std::isfinite(v)) return std::nullopt;
  return Error{fmt::format("ToEntityState: {} is {}", field, v)};
}
std::optional<Error> NonFinite(const LocalPoint& p, const char* field) {
  if (auto e = NonFinite(p.x_m, field)) return e;
  if (auto e = NonFinite(p.y_m, field)) return e;
  return NonFinite(p.z_m, field);
}
// The single-precision fields: finite inputs may still overflow a float.
std::optional<Error> NonFinite(const Vector3F& v, const char* field) {
  if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) return std::nullopt;
  return Error{fmt::format("ToEntityState: {} ({}, {}, {}) does not fit the PDU's floats", field,
                           v.x, v.y, v.z)};
}

std::optional<Error> BadMarking(const std::string& marking) {
  if (marking.size() > kMarkingChars) {
    return Error{fmt::format("ToEntityState: marking '{}' has {} characters (at most {})", marking,
                             marking.size(), kMarkingChars)};
  }
  // Without a branch per character: the marking is almost always printable.
  bool unprintable = false;
  for (char c : marking) unprintable |= (c < 0x20) | (c > 0x7E);
  if (unprintable) {
    return Error{fmt::format("ToEntityState: marking '{}' is not printable ASCII", marking)};
  }
  return std::nullopt;
}

// Which input is not finite, by name.
std::optional<Error> NonFiniteInput(const VehiclePose& pose) {
  if (auto e = NonFinite(pose.position_m, "position")) return e;
  if (auto e = NonFinite(pose.velocity_mps, "velocity")) return e;
  if (auto e = NonFinite(pose.acceleration_mps2, "acceleration")) return e;
  if (auto e = NonFinite(pose.attitude.heading_rad, "heading")) return e;
  if (auto e = NonFinite(pose.attitude.pitch_rad, "pitch")) return e;
  if (auto e = NonFinite(pose.attitude.roll_rad, "roll")) return e;
  for (double w : pose.angular_velocity_rad_s) {
    if (auto e = NonFinite(w, "angular velocity")) return e;
  }
  return std::nullopt;
}

// What Encode refuses: a float field that overflowed, or a location beyond a double.
std::optional<Error> BadOutput(const EntityStatePdu& pdu) {
  const WorldCoordinates& c = pdu.location;
  const Vector3F& v = pdu.linear_velocity;
  const Vector3F& a = pdu.dead_reckoning.linear_acceleration;
  const Vector3F& w = pdu.dead_reckoning.angular_velocity;
  const EulerAngles& o = pdu.orientation;
  // All finite is the rule: one test of every field, the naming below only when one is not.
  const float sum = v.x + v.y + v.z + a.x + a.y + a.z + w.x + w.y + w.z + o.psi + o.theta + o.phi;
  if (std::isfinite(sum) && std::isfinite(c.x + c.y + c.z)) return std::nullopt;
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
    return Error{fmt::format("ToEntityState: location ({}, {}, {}) is not finite", c.x, c.y, c.z)};
  }
  if (auto e = NonFinite(pdu.linear_velocity, "velocity")) return e;
  if (auto e = NonFinite(pdu.dead_reckoning.linear_acceleration, "acceleration")) return e;
  if (auto e = NonFinite(pdu.dead_reckoning.angular_velocity, "angular velocity")) return e;
  if (!std::isfinite(o.psi) || !std::isfinite(o.theta) || !std::isfinite(o.phi)) {
    return Error{fmt::format("ToEntityState: orientation ({}, {}, {}) is not finite", o.psi,
                             o.theta, o.phi)};
  }
  return std::nullopt;
}

}  // namespace

Result<EntityStatePdu> ToEntityState(const VehiclePose& pose, const GeodeticFrame& frame,
                                     const PduContext& context) {
  return ToEntityState(pose, TrigOf(pose.attitude), frame, context);
}

Result<EntityStatePdu> ToEntityState(const VehiclePose& pose, const AttitudeTrig& trig,
                                     const GeodeticFrame& frame, const PduContext& context) {
  if (auto e = BadMarking(pose.marking)) return *std::move(e);
  EntityStatePdu pdu;
  pdu.header.exercise_id = context.exercise_id;
  pdu.header.timestamp = context.timestamp;
  pdu.entity_id = pose.entity_id;
  pdu.force_id = pose.force_id;
  pdu.entity_type = pose.entity_type;
  pdu.alternative_entity_type = pose.entity_type;
  // Vectors and orientation in the terrain's axes at the entity (its grid north on a UTM ground).
  const GeodeticFrame::Axes at = frame.AxesAt(pose.position_m);
  pdu.linear_velocity = frame.VectorToGeocentric(pose.velocity_mps, at);
  pdu.location = frame.ToGeocentric(pose.position_m);
  pdu.orientation = frame.ToDisOrientationOf(trig, at);
  pdu.appearance = pose.appearance;
  pdu.dead_reckoning.algorithm = static_cast<uint8_t>(pose.dead_reckoning);
  pdu.dead_reckoning.linear_acceleration = frame.VectorToGeocentric(pose.acceleration_mps2, at);
  pdu.dead_reckoning.angular_velocity = {static_cast<float>(pose.angular_velocity_rad_s[0]),
                                         static_cast<float>(pose.angular_velocity_rad_s[1]),
                                         static_cast<float>(pose.angular_velocity_rad_s[2])};
  pdu.marking.character_set = kMarkingAscii;
  std::copy(pose.marking.begin(), pose.marking.end(), pdu.marking.characters.begin());
  // A non-finite input makes a non-finite output (NaN and infinity propagate through every
  // conversion), so the output's checks cover both; the input's run only to name the field.
  if (auto e = BadOutput(pdu)) {
    if (auto named = NonFiniteInput(pose)) return *std::move(named);
    return *std::move(e);
  }
  return pdu;
}

Result<VehiclePose> FromEntityState(const EntityStatePdu& pdu, const GeodeticFrame& frame) {
  if (pdu.entity_id.entity == 0 || pdu.entity_id.entity >= kFirstReservedEntityNumber) {
    return Error{fmt::format("entity {}:{}:{} has a reserved entity number (entities are 1..{})",
                             pdu.entity_id.site, pdu.entity_id.application, pdu.entity_id.entity,
                             kFirstReservedEntityNumber - 1)};
  }
  if (pdu.dead_reckoning.algorithm > kMaxDeadReckoningAlgorithm) {
    return Error{fmt::format("entity {}:{}:{}: dead-reckoning algorithm {} (0..{} defined)",
                             pdu.entity_id.site, pdu.entity_id.application, pdu.entity_id.entity,
                             pdu.dead_reckoning.algorithm, kMaxDeadReckoningAlgorithm)};
  }
  VehiclePose pose;
  pose.entity_id = pdu.entity_id;
  pose.entity_type = pdu.entity_type;
  pose.force_id = pdu.force_id;
  if (pdu.marking.character_set == kMarkingAscii) {
    // Up to the first NUL, in one assignment rather than a push_back per character.
    const auto& chars = pdu.marking.characters;
    size_t n = 0;
    while (n < chars.size() && chars[n] != '\0') ++n;
    pose.marking.assign(chars.data(), n);
  }
  pose.position_m = frame.FromGeocentric(pdu.location);
  const GeodeticFrame::Axes at = frame.AxesAt(pose.position_m);
  pose.attitude = frame.FromDisOrientation(pdu.orientation, at);
  pose.velocity_mps = frame.VectorFromGeocentric(pdu.linear_velocity, at);
  pose.acceleration_mps2 = frame.VectorFromGeocentric(pdu.dead_reckoning.linear_acceleration, at);
  pose.angular_velocity_rad_s = {pdu.dead_reckoning.angular_velocity.x,
                                 pdu.dead_reckoning.angular_velocity.y,
                                 pdu.dead_reckoning.angular_velocity.z};
  pose.appearance = pdu.appearance;
  pose.dead_reckoning = static_cast<DeadReckoningAlgorithm>(pdu.dead_reckoning.algorithm);
  const LocalPoint& p = pose.position_m;
  if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) {
    return Error{fmt::format("entity {}:{}:{}: location ({}, {}, {}) is not finite in local metres",
                             pdu.entity_id.site, pdu.entity_id.application, pdu.entity_id.entity,
                             pdu.location.x, pdu.location.y, pdu.location.z)};
  }
  return pose;
}

}  // namespace dt::dis
