// dt_render: renders a saved terrain file to a PNG, as a top-down map or a perspective view.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "render/png_io.h"
#include "render/renderer.h"
#include "terrain/terrain_file.h"

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Exit codes: 0 written, 1 bad input (unreadable terrain, unwritable PNG, bad values), 2 usage.
int Run(int argc, char** argv) {
  CLI::App app{"Render a saved dynterrain terrain file to a PNG (offscreen, CPU only)."};
  std::string terrain_path, out_path, camera = "map";
  int width_px = 1024, height_px = 768;
  std::vector<double> eye, target, area;
  double fov_deg = 60.0, grid_m = 0.0;
  bool no_scale_bar = false;
  std::vector<std::vector<double>> vehicles;
  app.add_option("terrain", terrain_path, "Terrain file (terrain/terrain_file.h)")->required();
  app.add_option("-o,--out", out_path, "PNG to write")->required();
  app.add_option("--camera", camera, "map (top-down, north up) or perspective")
      ->check(CLI::IsMember({"map", "perspective"}));
  app.add_option("--width", width_px, "Image width in pixels (map height follows the area)");
  app.add_option("--height", height_px, "Image height in pixels (perspective only)");
  app.add_option("--area", area, "Map area min_x,min_z,max_x,max_z in metres (default: all)")
      ->expected(4)
      ->delimiter(',');
  app.add_option("--eye", eye, "Perspective eye x,y,z in metres")->expected(3)->delimiter(',');
  app.add_option("--target", target, "Perspective target x,y,z in metres")
      ->expected(3)
      ->delimiter(',');
  app.add_option("--fov-deg", fov_deg, "Perspective vertical field of view in degrees");
  app.add_option("--grid-m", grid_m, "Grid overlay spacing in metres (0: none)");
  app.add_flag("--no-scale-bar", no_scale_bar, "Leave out the map's scale bar");
  app.add_option("--vehicle", vehicles,
                 "A vehicle x,z,heading_deg[,pitch_deg,roll_deg] standing on the surface; repeat")
      ->expected(1, 1000)
      ->allow_extra_args(false)
      ->delimiter(',');
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  auto loaded = dt::LoadTerrain(terrain_path);
  if (!loaded) {
    std::fprintf(stderr, "dt_render: %s\n", loaded.error().message.c_str());
    return 1;
  }
  const dt::Terrain& terrain = *loaded.value();
  try {
    std::vector<dt::VehicleSprite> sprites;
    for (const std::vector<double>& v : vehicles) {
      if (v.size() != 3 && v.size() != 5) {
        throw std::invalid_argument(
            fmt::format("--vehicle takes 3 or 5 comma-separated values, got {}", v.size()));
      }
      dt::VehicleSprite s;
      s.x_m = v[0];
      s.z_m = v[1];
      s.y_m = terrain.ElevationAt(s.x_m, s.z_m);  // throws off the terrain
      s.heading_rad = v[2] * kDegToRad;
      if (v.size() == 5) {
        s.pitch_rad = v[3] * kDegToRad;
        s.roll_rad = v[4] * kDegToRad;
      }
      sprites.push_back(s);
    }
    const double size_x = terrain.ground().size_x_m(), size_z = terrain.ground().size_z_m();
    const double size = std::max(size_x, size_z);
    // The whole terrain across the given width; the height follows its aspect.
    dt::Camera cam = dt::Camera::MapOf({0.0, 0.0, size_x, size_z}, width_px);
    if (camera == "map") {
      if (!area.empty()) cam = dt::Camera::MapOf({area[0], area[1], area[2], area[3]}, width_px);
    } else {
      // From beyond the south-west corner, looking at the centre.
      if (eye.empty()) eye = {-0.2 * size_x, 0.5 * size, -0.2 * size_z};
      if (target.empty()) target = {0.5 * size_x, 0.0, 0.5 * size_z};
      cam = dt::Camera::Perspective({eye[0], eye[1], eye[2]}, {target[0], target[1], target[2]},
                                    fov_deg * kDegToRad, width_px, height_px, 1.0,
                                    std::max(50000.0, 4.0 * size));
    }
    dt::RenderOptions options;
    options.grid_spacing_m = grid_m;
    options.scale_bar = !no_scale_bar;
    dt::Renderer renderer;
    const dt::Image image = renderer.Render(terrain, sprites, cam, options);
    if (auto s = dt::WritePng(image, out_path); !s) {
      std::fprintf(stderr, "dt_render: %s\n", s.error().message.c_str());
      return 1;
    }
    std::printf("dt_render: wrote %s (%d x %d px, %zu features)\n", out_path.c_str(), image.width(),
                image.height(), terrain.feature_count());
  } catch (const std::exception& e) {
    // Bad values on the command line: the renderer and camera name them.
    std::fprintf(stderr, "dt_render: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return Run(argc, argv); }
