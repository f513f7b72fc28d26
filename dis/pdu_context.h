// PduContext: the header fields a mapping to DIS takes from the gateway, not from the state.
#pragma once

#include <cstdint>

namespace dt::dis {

struct PduContext {
  uint8_t exercise_id = 1;
  uint32_t timestamp = 0;  // DIS time stamp (pdu/dis_time.h)
};

}  // namespace dt::dis
