#include "render/renderer.h"

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "render/bridge_mesh.h"
#include "render/gl_context.h"
#include "render/grid_overlay.h"
#include "render/mesh.h"
#include "render/scale_bar.h"
#include "render/terrain_mesh.h"
#include "terrain/bridge.h"

namespace dt {
namespace {

// Rows of grid squares meshed and drawn at a time: bounds memory on big terrains.
constexpr int kRowsPerBatch = 64;

void DrawMesh(const Mesh& mesh) {
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  if (mesh.triangle_vertex_count() > 0) {
    glVertexPointer(3, GL_FLOAT, 0, mesh.triangle_xyz.data());
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, mesh.triangle_rgba.data());
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(mesh.triangle_vertex_count()));
  }
  if (mesh.line_vertex_count() > 0) {
    glVertexPointer(3, GL_FLOAT, 0, mesh.line_xyz.data());
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, mesh.line_rgba.data());
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(mesh.line_vertex_count()));
  }
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
}

void CheckOptions(const RenderOptions& o) {
  if (!(o.grid_spacing_m >= 0.0) || !std::isfinite(o.grid_spacing_m) || o.max_subdivisions < 1) {
    throw std::invalid_argument(
        fmt::format("render options: grid_spacing_m {} must be >= 0, max_subdivisions {} >= 1",
                    o.grid_spacing_m, o.max_subdivisions));
  }
}

// The squares [first, end) that can appear: for a map, those under its area (looking straight
// down, nothing outside it projects into the image); for a perspective view, all of them.
std::pair<SquareIndex, SquareIndex> VisibleSquares(const Terrain& terrain, const Camera& camera) {
  const int mx = terrain.ground().squares_x(), mz = terrain.ground().squares_z();
  if (camera.kind() != CameraKind::kMap) return {{0, 0}, {mx, mz}};
  const Rect area = camera.map_area();
  const double s = terrain.ground().spacing_m();
  auto index = [&](double v, int m) {
    return static_cast<int>(std::clamp(std::floor(v / s), 0.0, static_cast<double>(m)));
  };
  const SquareIndex first{index(area.min_x, mx), index(area.min_z, mz)};
  const SquareIndex end{std::max(first.i, std::min(mx, index(area.max_x, mx) + 1)),
                        std::max(first.j, std::min(mz, index(area.max_z, mz) + 1))};
  return {first, end};
}

}  // namespace

Renderer::Renderer() : context_(std::make_unique<GlContext>()) {}
Renderer::~Renderer() = default;

Image Renderer::Render(const Terrain& terrain, std::span<const VehicleSprite> vehicles,
                       const Camera& camera, const RenderOptions& options) {
  CheckOptions(options);
  Mesh extras;  // validate the vehicles before touching GL state
  for (const VehicleSprite& v : vehicles) AppendVehicle(v, extras);
  for (const Feature* f : terrain.FeaturesById()) {
    if (f->type() == FeatureType::kBridge) {
      AppendBridge(static_cast<const Bridge&>(*f), terrain, extras);
    }
  }
  const TerrainMeshOptions mesh_options{.min_sample_m = camera.pixel_footprint_m(),
                                        .max_subdivisions = options.max_subdivisions};
  const int subdivisions = EarthworkSubdivisions(terrain, mesh_options);
  if (options.grid_spacing_m > 0.0) {
    AppendGridLines(terrain, options.grid_spacing_m, subdivisions, options.grid_colour, extras);
  }

  const int w = camera.width_px(), h = camera.height_px();
  context_->Bind(w, h);
  const Rgba bg = options.background;
  glClearColor(bg[0] / 255.0f, bg[1] / 255.0f, bg[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_LIGHTING);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DITHER);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glShadeModel(GL_SMOOTH);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(camera.projection().data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(camera.view().data());

  // The ground is pushed back slightly so ramp feet, grid lines and vehicles resting on it win
  // the depth test.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  const ElevationRange range =
      options.elevation_range_m
          ? ElevationRange{options.elevation_range_m->first, options.elevation_range_m->second}
          : GroundElevationRange(terrain.ground());
  const auto [first, end] = VisibleSquares(terrain, camera);
  Mesh batch;
  for (int j = first.j; j < end.j; j += kRowsPerBatch) {
    batch.Clear();
    AppendTerrainSquares(terrain, {first.i, j}, {end.i, std::min(end.j, j + kRowsPerBatch)},
                         subdivisions, range, batch);
    DrawMesh(batch);
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  DrawMesh(extras);
  glFinish();

  Image image(w, h);
  image.bytes() = context_->pixels();
  if (camera.kind() == CameraKind::kMap && options.scale_bar) {
    DrawScaleBar(image, camera.metres_per_pixel());
  }
  return image;
}

}  // namespace dt
