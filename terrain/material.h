// Material: the soil or construction material of ground triangles and features.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace dt {

// Values are part of the PDU and save-file formats: append, never renumber.
enum class Material : uint16_t {
  kFromGround = 0,  // a feature takes the material of the ground under its placement point
  kGrass = 1,
  kDirt = 2,
  kSand = 3,
  kRock = 4,
  kMud = 5,
  kGravel = 6,
  kConcrete = 7,
  kAsphalt = 8,
  kSteel = 9,
  kWater = 10,  // standing water (a flooded area below its level)
  kBurnt = 11,  // burnt ground
  kOil = 12,    // ground slick with spilt oil
};

inline constexpr uint16_t kMaterialCount = 13;

// Lower-case name ("grass", "from_ground"), as used in configs and commands.
std::string_view MaterialName(Material material);

// Parses a name from MaterialName; nullopt if unknown.
std::optional<Material> ParseMaterial(std::string_view name);

// True if the raw value names a Material.
inline bool IsValidMaterial(uint16_t raw) { return raw < kMaterialCount; }

}  // namespace dt
