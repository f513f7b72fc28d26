// Contact surface: the height, normal and material a vehicle contact meets at a ground point.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "base/feature_id.h"
#include "base/rect.h"
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
// the hull instead (hull_collision.h). Where no earthwork raises the surface above the ground
// (a crater's floor included) the ground triangle gives the normal and the soil; on an earthwork
// the normal comes from forward differences 0.1 m long and the soil from Terrain::SoilAt. (x, z)
// must be on the terrain.
SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m);

// The bare ground plane last found around one contact: a rectangle of a bitgrid cell where no
// feature raises or cuts the ground (the whole cell where none covers it), clipped to one
// triangle. Valid while the terrain does not change (callers reset it between
// terrain updates); a point inside it needs no grid look-up.
struct GroundPlaneCache {
  bool valid = false;
  uint64_t stamp = 0;  // the terrain's stamp when filled (Terrain::stamp): another's is stale
  double x0 = 0, z0 = 0, x1 = 0, z1 = 0;  // the cell
  double square_x0 = 0, square_z0 = 0, inverse_spacing = 0;
  bool upper = false;                       // which triangle of the square
  double h0 = 0, slope_x = 0, slope_z = 0;  // height = h0 + slope_x (x - x0) + slope_z (z - z0)
  Eigen::Vector3d normal{0.0, 1.0, 0.0};
  Material material = Material::kGrass;

  // True if the plane holds at (x, z) (valid, in the rectangle and on its triangle). The cell's
  // far edges belong to the next cell, as HeightGrid::Locate's truncation decides.
  bool Holds(double x_m, double z_m) const {
    return valid && x_m >= x0 && x_m < x1 && z_m >= z0 && z_m < z1 &&
           ((x_m - square_x0) * inverse_spacing + (z_m - square_z0) * inverse_spacing >= 1.0) ==
               upper;
  }
  // The plane's height at (x, z), where it Holds.
  double HeightAt(double x_m, double z_m) const {
    return h0 + slope_x * (x_m - x0) + slope_z * (z_m - z0);
  }
};

// SampleSurface, answering from and refilling `cache` where the ground is bare.
SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids, double x_m,
                            double z_m, double reach_m, GroundPlaneCache& cache);

// True if the bounds of a crater or berm indexed in the squares the rectangle touches overlap
// it: only there can the surface rise between a vehicle's always-sampled contacts.
bool EarthworkNear(const Terrain& terrain, const Rect& area);

// An earthwork near a vehicle and its bounds, kept by the vehicle while the terrain's stamp holds
// (Terrain::stamp): asking it is local, where the terrain's own index reaches into the features'
// scattered memory for every point.
struct NearEarthwork {
  const Feature* feature = nullptr;
  Rect bounds;
};

// The earthworks whose bounds overlap `area` (every one of them, as EarthworksNear gathers):
// at a point inside `area` that none of their bounds holds, no feature raises or cuts the ground.
struct KnownEarthworks {
  std::span<const NearEarthwork> near;
  Rect area;
};

// SampleSurface with `cache`, the same answer; in a bitgrid cell that features cover, a point
// inside `known.area` outside every one of `known.near` is ground without asking the terrain's
// features (which reaches into their scattered memory), and the ground plane is kept in `cache`
// over the part of the cell inside `known.area` when that part is clear of all of `known.near`.
SurfaceSample SampleSurface(const Terrain& terrain, std::span<const Solid> solids,
                            const KnownEarthworks& known, double x_m, double z_m, double reach_m,
                            GroundPlaneCache& cache);

// Every crater and berm whose bounds overlap `area`, each once, into `out` (cleared first).
void EarthworksNear(const Terrain& terrain, const Rect& area, std::vector<NearEarthwork>& out);

// True if the bounds of one of `near` overlap `area`: EarthworkNear's answer for any area inside
// the one `near` was gathered over.
bool AnyOverlaps(std::span<const NearEarthwork> near, const Rect& area);

// Terrain::ElevationAt(x, z), the same bits, where the bounds of one of `near` (gathered over an
// area holding the point) hold the point: the ground plus the highest raise plus the deepest cut
// of the earthworks over it (into `elevation_m`, true); false, and nothing asked of the ground,
// elsewhere.
bool EarthworkElevationAt(const Terrain& terrain, std::span<const NearEarthwork> near, double x_m,
                          double z_m, double& elevation_m);

}  // namespace dt
