// Contact surface: the height, normal and material a vehicle contact meets at a ground point.
#pragma once

#include <span>

#include <Eigen/Core>

#include "terrain/feature_id.h"
#include "terrain/material.h"
#include "terrain/terrain.h"
#include "vehicle/bridge_solids.h"

namespace dt {

struct SurfaceSample {
  double height_m = 0.0;
  Eigen::Vector3d normal{0.0, 1.0, 0.0};  // unit, upward (y up, docs/conventions.md)
  Material material = Material::kGrass;
  FeatureId bridge;  // the bridge whose deck slab this is the top of; number 0 otherwise
};

// The whole surface under (x, z) as seen from a contact at height `reach_m` and above: the ground
// with its craters and berms (Terrain::ElevationAt, Terrain::SoilAt), raised to the top of any
// bridge solid over the point whose top is at or below `reach_m`. So a contact on a deck stands
// on it, one under a deck meets the ground, and a solid top above `reach_m` is an obstacle for
// the hull instead (hull_collision.h). Bare squares take their normal from the ground triangle;
// where earthworks may lie, from central differences 0.1 m apart. (x, z) must be on the terrain.
SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m);

// True if the feature bitgrid (terrain.h) has a cell set anywhere in the rectangle (clipped to
// the terrain): earthworks or a bridge may lie there. Where it is false the surface is the
// ground's triangles.
bool FeatureCellsIn(const Terrain& terrain, const Rect& area);

}  // namespace dt
