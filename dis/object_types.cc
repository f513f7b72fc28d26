#include "dis/object_types.h"

namespace dt::dis {

uint32_t PackCraterAppearance(const CraterAppearance& a) {
  return uint32_t{a.diameter_m} | (uint32_t{a.depth_cm} << 8) | (uint32_t{a.height_cm} << 16);
}

CraterAppearance UnpackCraterAppearance(uint32_t specific) {
  return {static_cast<uint8_t>(specific & 0xFF), static_cast<uint8_t>((specific >> 8) & 0xFF),
          static_cast<uint8_t>((specific >> 16) & 0xFF)};
}

}  // namespace dt::dis
