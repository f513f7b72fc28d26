// Bridge mesh: a bridge's deck, sides and piers; a destroyed span sags to the ground.
#pragma once

#include "render/mesh.h"
#include "terrain/bridge.h"
#include "terrain/terrain.h"

namespace dt {

// Thickness of the drawn deck below its driving surface, and of the piers along the bridge.
inline constexpr double kBridgeDeckThicknessM = 1.0;
inline constexpr double kBridgePierThicknessM = 1.0;

// Appends the bridge: the deck surface between consecutive cross-sections of
// Bridge::DeckProfile (so a destroyed span is drawn with its middle on the ground, thesis IV.C),
// the deck's side faces, and a pier under each joint of ramp and span from the ground to the
// deck's underside. Colours are the bridge material, flat-shaded.
void AppendBridge(const Bridge& bridge, const Terrain& terrain, Mesh& mesh);

}  // namespace dt
