#include "dis/vehicle_mapping.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace dt::dis {
namespace {

void RequireFinite(double v, const char* field) {
  if (!std::isfinite(v))
    throw std::invalid_argument(fmt::format("ToEntityState: {} is {}", field, v));
}
void RequireFinite(const LocalPoint& p, const char* field) {
  RequireFinite(p.x_m, field);
  RequireFinite(p.y_m, field);
  RequireFinite(p.z_m, field);
}

}  // namespace

EntityStatePdu ToEntityState(const VehiclePose& pose, const GeodeticFrame& frame,
                             const PduContext& context) {
  RequireFinite(pose.position_m, "position");
  RequireFinite(pose.velocity_mps, "velocity");
  RequireFinite(pose.acceleration_mps2, "acceleration");
  RequireFinite(pose.attitude.heading_rad, "heading");
  RequireFinite(pose.attitude.pitch_rad, "pitch");
  RequireFinite(pose.attitude.roll_rad, "roll");
  for (double w : pose.angular_velocity_rad_s) RequireFinite(w, "angular velocity");
  if (pose.marking.size() > kMarkingChars) {
    throw std::invalid_argument(
        fmt::format("ToEntityState: marking '{}' has {} characters (at most {})", pose.marking,
                    pose.marking.size(), kMarkingChars));
  }
  for (char c : pose.marking) {
    if (c < 0x20 || c > 0x7E) {
      throw std::invalid_argument(
          fmt::format("ToEntityState: marking '{}' is not printable ASCII", pose.marking));
    }
  }
  EntityStatePdu pdu;
  pdu.header.exercise_id = context.exercise_id;
  pdu.header.timestamp = context.timestamp;
  pdu.entity_id = pose.entity_id;
  pdu.force_id = pose.force_id;
  pdu.entity_type = pose.entity_type;
  pdu.alternative_entity_type = pose.entity_type;
  pdu.linear_velocity = frame.VectorToGeocentric(pose.velocity_mps);
  pdu.location = frame.ToGeocentric(pose.position_m);
  pdu.orientation = frame.ToDisOrientation(pose.attitude);
  pdu.appearance = pose.appearance;
  pdu.dead_reckoning.algorithm = static_cast<uint8_t>(pose.dead_reckoning);
  pdu.dead_reckoning.linear_acceleration = frame.VectorToGeocentric(pose.acceleration_mps2);
  pdu.dead_reckoning.angular_velocity = {static_cast<float>(pose.angular_velocity_rad_s[0]),
                                         static_cast<float>(pose.angular_velocity_rad_s[1]),
                                         static_cast<float>(pose.angular_velocity_rad_s[2])};
  pdu.marking.character_set = kMarkingAscii;
  std::copy(pose.marking.begin(), pose.marking.end(), pdu.marking.characters.begin());
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
    for (char c : pdu.marking.characters) {
      if (c == '\0') break;
      pose.marking.push_back(c);
    }
  }
  pose.position_m = frame.FromGeocentric(pdu.location);
  pose.attitude = frame.FromDisOrientation(pdu.orientation);
  pose.velocity_mps = frame.VectorFromGeocentric(pdu.linear_velocity);
  pose.acceleration_mps2 = frame.VectorFromGeocentric(pdu.dead_reckoning.linear_acceleration);
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
