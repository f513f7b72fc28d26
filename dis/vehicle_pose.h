// VehiclePose: the state of one vehicle the DIS mapping needs, in the terrain's axes.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "dis/dis_pdu.h"
#include "dis/geodetic_frame.h"

namespace dt::dis {

// Positions and vectors in the terrain's axes (x east, y up, z north); attitude in its
// convention (docs/conventions.md). Angular velocity is about the body axes x forward, y right,
// z down (DIS's body axes), rad/s.
struct VehiclePose {
  EntityId entity_id;
  EntityType entity_type;
  uint8_t force_id = 0;
  std::string marking;  // ASCII, at most 11 characters
  LocalPoint position_m;
  LocalAttitude attitude;
  LocalPoint velocity_mps;
  LocalPoint acceleration_mps2;
  std::array<double, 3> angular_velocity_rad_s{};
  uint32_t appearance = 0;
  DeadReckoningAlgorithm dead_reckoning = DeadReckoningAlgorithm::kFpw;
};

}  // namespace dt::dis
