// Material: the soil or construction material of ground triangles and features.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "base/enum_list.h"

namespace dt {

// One X(enumerator, value, name) per material (base/enum_list.h); the name is lower case, as
// used in configs and commands. Values are part of the PDU and save-file formats: append, never
// renumber.
#define DT_MATERIALS(X)                                                      \
  /* a feature takes the material of the ground under its placement point */ \
  X(kFromGround, 0, "from_ground")                                           \
  X(kGrass, 1, "grass")                                                      \
  X(kDirt, 2, "dirt")                                                        \
  X(kSand, 3, "sand")                                                        \
  X(kRock, 4, "rock")                                                        \
  X(kMud, 5, "mud")                                                          \
  X(kGravel, 6, "gravel")                                                    \
  X(kConcrete, 7, "concrete")                                                \
  X(kAsphalt, 8, "asphalt")                                                  \
  X(kSteel, 9, "steel")                                                      \
  /* standing water (a flooded area below its level) */                      \
  X(kWater, 10, "water")                                                     \
  /* burnt ground */                                                         \
  X(kBurnt, 11, "burnt")                                                     \
  /* ground slick with spilt oil */                                          \
  X(kOil, 12, "oil")

enum class Material : uint16_t { DT_MATERIALS(DT_ENUM_ENUMERATOR) };

inline constexpr uint16_t kMaterialCount = 0 DT_MATERIALS(DT_ENUM_PLUS_ONE);
// Values run 0, 1, 2, ... in the list's order, so a value indexes tables of kMaterialCount.
static_assert(EnumValuesRunOn({DT_MATERIALS(DT_ENUM_VALUE)}, 0));

// Lower-case name ("grass", "from_ground"), as used in configs and commands.
std::string_view MaterialName(Material material);

// Parses a name from MaterialName; nullopt if unknown.
std::optional<Material> ParseMaterial(std::string_view name);

// True if the raw value names a Material.
inline bool IsValidMaterial(uint16_t raw) { return raw < kMaterialCount; }

}  // namespace dt
