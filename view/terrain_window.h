// TerrainWindow: the ground, earthworks and bridge solids around a point, for the page's 3D view.
#pragma once

#include <string>

#include "base/result.h"
#include "terrain/terrain.h"

namespace dt {

// Posts per side of a window: the page asks for at most this many, whatever the terrain's size,
// so a reply stays bounded (257^2 heights) and a large terrain is seen at a coarser step.
inline constexpr int kMaxWindowPosts = 257;
// Bridges listed in one window at most (each is a handful of solids).
inline constexpr int kMaxWindowBridges = 512;

struct TerrainWindowRequest {
  double x_m = 0.0, z_m = 0.0;  // the centre
  double half_m = 0.0;          // half the side of the square asked for
  int posts = 129;              // posts per side asked for, 2..kMaxWindowPosts
};

// Parses "x=<m>&z=<m>&half=<m>[&posts=<n>]" (the query of GET /terrain3d); the error names the
// key and its value. The centre need not be on the terrain: the window is clipped to it.
Result<TerrainWindowRequest> ParseTerrainWindowQuery(const std::string& query);

// The window as JSON (docs/view.md "The 3D view"): a grid of `nx` x `nz` samples from (x0, z0)
// every `step` metres, row by row along x, on the lattice of that step from the terrain's origin
// (so a window that moves keeps its samples): the step is whole post spacings for a window wider
// than its posts, else a power-of-two fraction of the spacing down to an eighth. `h` holds the
// surface (Terrain::ElevationAt: ground plus earthworks) and `d` the earthworks' part of it
// (surface minus bare ground: negative in a crater's floor or a ditch, positive on a rim or a
// berm); `solids` are the solids of every bridge whose bounds meet the window
// (vehicle/bridge_solids.h BridgeSolids: the faces vehicles drive on and stop against).
std::string TerrainWindowJson(const Terrain& terrain, const TerrainWindowRequest& request);

}  // namespace dt
