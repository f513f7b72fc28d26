// Enums made from one X-macro list, so that an enumerator, its name and the count cannot drift.
#pragma once

#include <cstddef>

// An enum whose enumerators each need a name (for logs, configs, reports), and often a count
// (for tables indexed by value), is written as one list of X(enumerator, value, "name"), and the
// enum, its count and its names are all made from that list: nothing can be added to one of them
// without the others. terrain/material.h is an example:
//
//   #define DT_MATERIALS(X) X(kFromGround, 0, "from_ground") X(kGrass, 1, "grass") ...
//   enum class Material : uint16_t { DT_MATERIALS(DT_ENUM_ENUMERATOR) };
//   inline constexpr uint16_t kMaterialCount = 0 DT_MATERIALS(DT_ENUM_PLUS_ONE);
//   static_assert(dt::EnumValuesRunOn({DT_MATERIALS(DT_ENUM_VALUE)}, 0));
//   constexpr std::string_view kNames[] = {DT_MATERIALS(DT_ENUM_NAME)};  // in the .cc
//
// The values are written out rather than left to their place in the list: they are on the wire
// and in files, and a line moved must not renumber the enumerators below it. The static_assert
// holds them to the list's order without gaps, so value - first indexes a table made from it.
#define DT_ENUM_ENUMERATOR(enumerator, value, name) enumerator = value,
#define DT_ENUM_PLUS_ONE(enumerator, value, name) +1
#define DT_ENUM_VALUE(enumerator, value, name) value,
#define DT_ENUM_NAME(enumerator, value, name) name,

namespace dt {

// True if `values` are first, first + 1, first + 2, ... in order.
template <size_t N>
constexpr bool EnumValuesRunOn(const int (&values)[N], int first) {
  for (size_t i = 0; i < N; ++i) {
    if (values[i] != first + static_cast<int>(i)) return false;
  }
  return true;
}

}  // namespace dt
