// Bridge mesh: a bridge drawn as the solids the vehicles meet (deck slabs, piers, fallen span).
#pragma once

#include "render/mesh.h"
#include "terrain/bridge.h"
#include "terrain/terrain.h"

namespace dt {

// Appends the bridge as the closed boxes of vehicle/bridge_solids.h's BridgeSolids, the one
// geometry of a bridge: a slab for each ramp and the span (kDeckThicknessM thick), a pier column
// under each deck edge at each joint, and for a destroyed bridge the rubble of its span on the
// ground between the piers (docs/vehicles.md "Bridges as solids"). So a vehicle drawn beside,
// under or on a bridge is where the physics put it against the same faces. Colours are the
// bridge material, flat-shaded.
void AppendBridge(const Bridge& bridge, const Terrain& terrain, Mesh& mesh);

}  // namespace dt
