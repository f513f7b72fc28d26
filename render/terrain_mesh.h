// Terrain mesh: the ground and its earthworks as shaded, coloured triangles.
#pragma once

#include "render/mesh.h"
#include "terrain/terrain.h"

namespace dt {

struct TerrainMeshOptions {
  // Never sample earthworks finer than this (the renderer passes the camera's pixel footprint:
  // finer detail could not show). 0 leaves the limit to max_subdivisions.
  double min_sample_m = 0.0;
  // Most sub-squares per grid-square side where earthworks lie.
  int max_subdivisions = 16;
};

// Sub-squares per grid-square side used in squares that hold earthworks: enough to sample the
// smallest earthwork's detail (a crater's ring spacing, a berm's slope), within the options.
// One value for the whole terrain, so neighbouring refined squares share their edge vertices.
// Depends only on the set of features, not on the order they were added.
int EarthworkSubdivisions(const Terrain& terrain, const TerrainMeshOptions& options);

// The elevation range the elevation tint spans: lowest and highest ground post.
struct ElevationRange {
  double lowest_m = 0.0;
  double highest_m = 0.0;
};
ElevationRange GroundElevationRange(const HeightGrid& ground);

// Appends squares [first.i, end.i) x [first.j, end.j) to `mesh`. Squares without
// earthworks are the grid's two triangles coloured by their soil; squares holding an earthwork
// are sampled `subdivisions` times per side through Terrain::ElevationAt and coloured by the
// topmost earthwork's material, tinted (palette.h). A plain square next to a refined one takes
// the refined square's vertices along their shared edge, so no T-junction leaves a pinhole.
// Every triangle is flat-shaded by its slope and each vertex tinted by its elevation within
// `range`. Throws std::invalid_argument for squares outside the grid or subdivisions < 1.
void AppendTerrainSquares(const Terrain& terrain, SquareIndex first, SquareIndex end,
                          int subdivisions, const ElevationRange& range, Mesh& mesh);

// The topmost earthwork (crater or berm) covering (x, z) among the features of `square`; ties go
// to the smaller ID so the answer does not depend on insertion order. nullptr if none.
const Feature* TopEarthworkAt(const Terrain& terrain, SquareIndex square, double x_m, double z_m);

}  // namespace dt
