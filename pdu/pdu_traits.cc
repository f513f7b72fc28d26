#include "pdu/pdu_traits.h"

namespace dt {

std::optional<NodeAddress> PeekSender(std::span<const uint8_t> bytes) {
  if (bytes.size() < kSenderOffset + 4) return std::nullopt;
  const uint8_t* p = bytes.data() + kSenderOffset;
  return NodeAddress{static_cast<uint16_t>((p[0] << 8) | p[1]),
                     static_cast<uint16_t>((p[2] << 8) | p[3])};
}

}  // namespace dt
