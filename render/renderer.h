// Renderer: draws a terrain state (ground, earthworks, bridges, vehicles) into an Image.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <utility>

#include "render/camera.h"
#include "render/image.h"
#include "render/vehicle_sprite.h"
#include "terrain/terrain.h"

namespace dt {

class GlContext;

struct RenderOptions {
  // Grid overlay every grid_spacing_m metres; 0 draws none.
  double grid_spacing_m = 0.0;
  Rgba grid_colour = {30, 30, 30, 255};
  // Map cameras only: a scale bar in the lower-left corner.
  bool scale_bar = true;
  // Most sub-squares per grid-square side where earthworks lie (TerrainMeshOptions).
  int max_subdivisions = 16;
  // The lowest and highest elevation of the ground's tint (palette.h ElevationFactor); unset:
  // the terrain's own lowest and highest post. Pieces of one picture drawn apart (the live view's
  // relief tiles) share the whole ground's, so they meet without a seam.
  std::optional<std::pair<double, double>> elevation_range_m;
  // Outside the terrain, and the sky of perspective views.
  Rgba background = {170, 200, 230, 255};
};

// Owns one off-screen OpenGL context (OSMesa, CPU only: no display, no GPU). The same terrain
// state, vehicles, camera and options give the same pixels on one machine: nothing depends on
// time, insertion order or threads (docs/rendering.md). Not thread-safe.
class Renderer {
 public:
  // Throws std::runtime_error if no OSMesa context can be made.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Throws std::invalid_argument for bad options or vehicles (vehicle_sprite.h).
  Image Render(const Terrain& terrain, std::span<const VehicleSprite> vehicles,
               const Camera& camera, const RenderOptions& options = {});

 private:
  std::unique_ptr<GlContext> context_;
};

}  // namespace dt
