#include "terrain/material.h"

#include <array>

namespace dt {
namespace {
constexpr std::array<std::string_view, kMaterialCount> kNames = {
    "from_ground", "grass",   "dirt",  "sand",  "rock",  "mud", "gravel",
    "concrete",    "asphalt", "steel", "water", "burnt", "oil"};
}  // namespace

std::string_view MaterialName(Material material) {
  const auto index = static_cast<uint16_t>(material);
  return index < kNames.size() ? kNames[index] : std::string_view("unknown");
}

std::optional<Material> ParseMaterial(std::string_view name) {
  for (uint16_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<Material>(i);
  }
  return std::nullopt;
}

}  // namespace dt
