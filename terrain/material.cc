#include "terrain/material.h"

#include <iterator>

namespace dt {
namespace {
constexpr std::string_view kNames[] = {DT_MATERIALS(DT_ENUM_NAME)};
static_assert(std::size(kNames) == kMaterialCount);
}  // namespace

std::string_view MaterialName(Material material) {
  const auto index = static_cast<uint16_t>(material);
  return index < std::size(kNames) ? kNames[index] : std::string_view("unknown");
}

std::optional<Material> ParseMaterial(std::string_view name) {
  for (uint16_t i = 0; i < std::size(kNames); ++i) {
    if (kNames[i] == name) return static_cast<Material>(i);
  }
  return std::nullopt;
}

}  // namespace dt
