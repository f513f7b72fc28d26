// ShippedFrictionTable: configs/friction.toml as built into the program, for processes that are
// given no friction file.
#pragma once

#include <string_view>

#include "terrain/friction_table.h"

namespace dt {

// The text of configs/friction.toml when the program was built.
std::string_view ShippedFrictionText();
// That text parsed once (it is checked by the build's own tests, so a parse failure is a broken
// build and aborts via the exception escaping main).
const FrictionTable& ShippedFrictionTable();

}  // namespace dt
