// TestBusConfig: the PduBusConfig of an in-process test bus (no key, the real clock).
#pragma once

#include <cstdint>

#include "transport/pdu_bus.h"

namespace dt::testing {

inline PduBusConfig TestBusConfig(NodeAddress local, uint8_t exercise_id, double terrain_size_m) {
  PduBusConfig c;
  c.exercise_id = exercise_id;
  c.local = local;
  c.terrain_size_x_m = c.terrain_size_z_m = terrain_size_m;
  return c;
}

}  // namespace dt::testing
