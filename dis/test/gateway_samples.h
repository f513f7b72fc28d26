// Gateway settings and tank states shared by the gateway's unit test and its benchmark.
#pragma once

#include <cstdint>
#include <string>

#include "dis/gateway_core.h"
#include "pdu/vehicle_state.h"

namespace dt::dis {

inline constexpr NodeAddress kSampleGateway{1, 60};

// dis-test.toml's origin; the gateway at kSampleGateway, a member with `node`.
inline GatewaySettings SampleSettings(uint8_t exercise_id, double terrain_size_m,
                                      NodeAddress node) {
  GatewaySettings s;
  s.origin = {36.6, -121.9, 20.0};
  s.exercise_id = exercise_id;
  s.terrain_size_x_m = s.terrain_size_z_m = terrain_size_m;
  s.self = kSampleGateway;
  s.members = {node, s.self};
  return s;
}

// A standing tank 12.5 m up, marked "tank-<number>" like a node's.
inline VehicleStateFields SampleTank(dt::EntityId id, double x_m, double z_m, double heading_rad) {
  VehicleStateFields s;
  s.id = id;
  s.type = *EntityTypeOfVehicle("tank");
  s.location_m = {x_m, 12.5, z_m};
  s.heading_rad = heading_rad;
  s.marking = "tank-" + std::to_string(id.entity);
  return s;
}

}  // namespace dt::dis
