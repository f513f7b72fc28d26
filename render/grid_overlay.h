// Grid overlay: lines draped on the terrain every so many metres, for reading positions.
#pragma once

#include "render/mesh.h"
#include "terrain/terrain.h"

namespace dt {

// Lines are lifted this far above the surface so they are not hidden inside it.
inline constexpr double kGridLiftM = 0.1;

// Appends lines along x = k * spacing_m and z = k * spacing_m (k = 0, 1, ...) across the
// terrain, following Terrain::ElevationAt at `samples_per_square` points per grid square.
// Throws std::invalid_argument unless spacing_m > 0 (finite) and samples_per_square >= 1.
void AppendGridLines(const Terrain& terrain, double spacing_m, int samples_per_square, Rgba colour,
                     Mesh& mesh);

}  // namespace dt
