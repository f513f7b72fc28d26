#include "dis/entity_translation.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "dis/vehicle_mapping.h"
#include "vehicle/dead_reckoning.h"

namespace dt::dis {
namespace {

// The exercise's own appearance bits, meaningless to outside DIS peers.
constexpr uint32_t kExerciseOnly = appearance::kOnBridge | appearance::kFalling;
// What an outside appearance may say to the exercise.
constexpr uint32_t kImported =
    appearance::kMobilityKill | appearance::kDamageMask | appearance::kDeactivated;

std::string IdText(const dis::EntityId& id) {
  return fmt::format("{}:{}:{}", id.site, id.application, id.entity);
}

dt::EntityType BuiltInTypeOf(const dis::EntityType& t) {
  const dt::EntityType exact{t.kind,        t.domain,   t.country, t.category,
                             t.subcategory, t.specific, t.extra};
  if (!VehicleNameOfEntityType(exact).empty()) return exact;
  const char* name = t.category == 1 ? "tank" : t.category == 6 ? "jeep" : "truck";
  return *EntityTypeOfVehicle(name);
}

dt::DeadReckoningAlgorithm AlgorithmOf(uint8_t dis) {
  if (dis >= 1 && dis <= 5) return static_cast<dt::DeadReckoningAlgorithm>(dis);
  if (dis >= 6 && dis <= 9) return static_cast<dt::DeadReckoningAlgorithm>(dis - 4);
  return dt::DeadReckoningAlgorithm::kFpw;
}

}  // namespace

Result<EntityStatePdu> EntityStateOfVehicle(const VehicleStateFields& s, const GeodeticFrame& frame,
                                            const PduContext& context) {
  return EntityStateOfVehicle(s, TrigOf({s.heading_rad, s.pitch_rad, s.roll_rad}), frame, context);
}

Result<EntityStatePdu> EntityStateOfVehicle(const VehicleStateFields& s, const AttitudeTrig& trig,
                                            const GeodeticFrame& frame, const PduContext& context) {
  VehiclePose pose;
  pose.entity_id = {s.id.site, s.id.application, s.id.entity};
  pose.entity_type = {s.type.kind,        s.type.domain,   s.type.country, s.type.category,
                      s.type.subcategory, s.type.specific, s.type.extra};
  pose.force_id = s.force_id;
  for (char c : s.marking) {
    if (c < 0x20 || c > 0x7E || pose.marking.size() == kMarkingChars) break;
    pose.marking.push_back(c);
  }
  pose.position_m = {s.location_m[0], s.location_m[1], s.location_m[2]};
  pose.attitude = {s.heading_rad, s.pitch_rad, s.roll_rad};
  pose.velocity_mps = {s.velocity_mps[0], s.velocity_mps[1], s.velocity_mps[2]};
  pose.acceleration_mps2 = {s.acceleration_mps2[0], s.acceleration_mps2[1], s.acceleration_mps2[2]};
  // The exercise's body axes are (ahead, up, left); DIS's (x forward, y right, z down).
  const auto& w = s.angular_velocity_body_rad_s;
  pose.angular_velocity_rad_s = {w[0], -w[2], -w[1]};
  pose.appearance = s.appearance & ~kExerciseOnly;
  pose.dead_reckoning = static_cast<DeadReckoningAlgorithm>(static_cast<uint8_t>(s.algorithm));
  return ToEntityState(pose, trig, frame, context);
}

Result<VehicleStateFields> VehicleOfEntityState(const EntityStatePdu& pdu,
                                                const GeodeticFrame& frame, double terrain_size_x_m,
                                                double terrain_size_z_m) {
  if (pdu.entity_type.kind != 1 || pdu.entity_type.domain != 1) {
    return Error{fmt::format("entity {}: type {}.{}.{} is no land platform (1.1)",
                             IdText(pdu.entity_id), pdu.entity_type.kind, pdu.entity_type.domain,
                             pdu.entity_type.country)};
  }
  Result<VehiclePose> pose = FromEntityState(pdu, frame);
  if (!pose.ok()) return pose.error();
  const VehiclePose& p = pose.value();
  if (!(p.position_m.x_m >= 0.0 && p.position_m.x_m <= terrain_size_x_m &&
        p.position_m.z_m >= 0.0 && p.position_m.z_m <= terrain_size_z_m)) {
    return Error{fmt::format("entity {} at ({:.1f}, {:.1f}) m is off the {} x {} m terrain",
                             IdText(pdu.entity_id), p.position_m.x_m, p.position_m.z_m,
                             terrain_size_x_m, terrain_size_z_m)};
  }
  VehicleStateFields s;
  s.id = {p.entity_id.site, p.entity_id.application, p.entity_id.entity};
  s.force_id = p.force_id <= kMaxForceId ? p.force_id : 0;
  s.type = BuiltInTypeOf(p.entity_type);
  s.location_m = {p.position_m.x_m, p.position_m.y_m, p.position_m.z_m};
  s.velocity_mps = {p.velocity_mps.x_m, p.velocity_mps.y_m, p.velocity_mps.z_m};
  s.acceleration_mps2 = {p.acceleration_mps2.x_m, p.acceleration_mps2.y_m, p.acceleration_mps2.z_m};
  s.heading_rad = p.attitude.heading_rad;
  s.pitch_rad = p.attitude.pitch_rad;
  s.roll_rad = p.attitude.roll_rad;
  const auto& w = p.angular_velocity_rad_s;
  s.angular_velocity_body_rad_s = {w[0], -w[2], -w[1]};
  s.appearance = p.appearance & kImported;
  s.algorithm = AlgorithmOf(static_cast<uint8_t>(p.dead_reckoning));
  // Up to the first unprintable character, in one assignment.
  size_t n = 0;
  while (n < p.marking.size() && p.marking[n] >= 0x20 && p.marking[n] <= 0x7E) ++n;
  s.marking.assign(p.marking, 0, n);
  return s;
}

}  // namespace dt::dis
