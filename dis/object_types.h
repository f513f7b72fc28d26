// The SISO-REF-010 object types and appearance records dynterrain's features map to
// (docs/dis.md "Features").
#pragma once

#include <cstdint>

#include "dis/dis_pdu.h"

namespace dt::dis {

// Crater: point object, land domain, obstacle kind, category 3 (SISO-REF-010).
inline constexpr ObjectType kCraterObjectType{1, 1, 3, 0};
// Bridge: point object, land domain, passageway kind (4); no category is defined for a plain
// bridge, so 0 (other).
inline constexpr ObjectType kBridgeObjectType{1, 4, 0, 0};
// Berm: no berm type exists in SISO-REF-010. A berm is sent as a linear object, land domain,
// obstacle kind, category 0 (other): an outside tool sees an obstacle line with a height and
// no depth; dynterrain reads back only this exact type as a berm.
inline constexpr ObjectType kBermObjectType{1, 1, 0, 0};

// Crater specific appearance (32 bits), as pinned in docs/dis.md: bits 0-7 diameter in
// metres, bits 8-15 depth below the bare ground in centimetres, bits 16-23 rim height above it
// in centimetres, bits 24-31 zero. Each field saturates at 255.
struct CraterAppearance {
  uint8_t diameter_m = 0;
  uint8_t depth_cm = 0;
  uint8_t height_cm = 0;
  bool operator==(const CraterAppearance&) const = default;
};
uint32_t PackCraterAppearance(const CraterAppearance& a);
CraterAppearance UnpackCraterAppearance(uint32_t specific);

}  // namespace dt::dis
