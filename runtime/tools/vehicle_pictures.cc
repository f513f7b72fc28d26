// dt_vehicle_pictures: renders the physical model's picture sequences of docs/vehicles.md
// ("Pictures"): a tank crossing a crater on one track, and a tank falling off a 6 m span. Each is
// one PNG of a few frames side by side, labelled with time, elevation, roll and damage.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "render/camera.h"
#include "render/montage.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "runtime/simulated_vehicle_sprite.h"
#include "terrain/height_grid.h"
#include "terrain/terrain.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/simulated_vehicle.h"

namespace {

constexpr double kTickS = 1.0 / 30.0;
constexpr double kDeg = 180.0 / std::numbers::pi;
constexpr int kFrameWidthPx = 320;
constexpr int kFrameHeightPx = 220;

// 400 m of flat grass at 10 m on 2 m posts: the thesis scenarios' ground
// (vehicle/test/thesis_scenario_test.cc).
std::unique_ptr<dt::Terrain> FlatTerrain() {
  return std::make_unique<dt::Terrain>(dt::HeightGrid(201, 2.0, 10.0f, dt::Material::kGrass));
}

// A demand from `from_s` on; the latest one whose time has come is in force.
struct Demand {
  double from_s, speed_mps, rate_rad_s;
};

struct Frame {
  double at_s;
  dt::Image image;
  std::string label;
};

// Drives the vehicle through the demands at 30 Hz ticks for `seconds`, rendering a frame at each
// of `shots_s` from a camera `eye_offset_m` away from the vehicle, looking at it.
std::vector<Frame> Sequence(dt::Renderer& renderer, const dt::Terrain& terrain,
                            dt::SimulatedVehicle& vehicle, const std::vector<Demand>& demands,
                            const std::vector<double>& shots_s,
                            const Eigen::Vector3d& eye_offset_m) {
  std::vector<Frame> frames;
  size_t next_demand = 0, next_shot = 0;
  const double end_s = shots_s.back();
  for (int tick = 0; next_shot < shots_s.size(); ++tick) {
    const double t_s = tick * kTickS;
    while (next_demand < demands.size() && demands[next_demand].from_s <= t_s + 1e-9) {
      const Demand& d = demands[next_demand++];
      if (vehicle.alive() && vehicle.physical()->mobile()) {
        if (dt::Status s = vehicle.Command(d.speed_mps, d.rate_rad_s); !s) {
          throw std::runtime_error(s.error().message);
        }
      }
    }
    while (next_shot < shots_s.size() && shots_s[next_shot] <= t_s + 1e-9) {
      const dt::VehiclePose p = vehicle.pose();
      const Eigen::Vector3d target(p.x_m, p.elevation_m + 1.0, p.z_m);
      const dt::Camera camera = dt::Camera::Perspective(target + eye_offset_m, target, 40.0 / kDeg,
                                                        kFrameWidthPx, kFrameHeightPx);
      const dt::VehicleSprite sprite = dt::SpriteOf(vehicle);
      dt::RenderOptions options;
      options.grid_spacing_m = 2.0;
      options.grid_colour = {60, 90, 50, 255};
      frames.push_back({t_s, renderer.Render(terrain, std::span(&sprite, 1), camera, options),
                        fmt::format("T {:.1f} S  Y {:.1f} M  ROLL {:.0f}  {}", t_s, p.elevation_m,
                                    p.roll_rad * kDeg, vehicle.damage_name())});
      ++next_shot;
    }
    if (t_s > end_s) break;
    if (dt::Result<dt::VehicleEvents> r = vehicle.Advance(terrain, kTickS); !r) {
      throw std::runtime_error(r.error().message);
    }
  }
  return frames;
}

void Write(const std::vector<Frame>& frames, const std::filesystem::path& path) {
  std::vector<dt::Image> images;
  std::vector<std::string> labels;
  for (const Frame& f : frames) {
    images.push_back(f.image);
    labels.push_back(f.label);
  }
  dt::MontageOptions options;
  options.columns = 3;
  options.label_scale = 1;
  if (dt::Status s = dt::WritePng(dt::Montage(images, labels, options), path.string()); !s) {
    throw std::runtime_error(s.error().message);
  }
  std::printf("%s: %zu frames\n", path.string().c_str(), frames.size());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Renders the physical vehicle model's picture sequences (docs/vehicles.md)"};
  std::string out_dir = "docs/images";
  app.add_option("--out", out_dir, "folder for vehicle-crater.png and vehicle-fall.png")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(out_dir);
    dt::Renderer renderer;
    const dt::PhysicalVehicleType tank =
        dt::BuiltInPhysicalType("tank", dt::ShippedFrictionTable()).value();

    // A tank heading east at 4 m/s with its left (north) track over the rim of a 10 m crater
    // (rim 1.5 m high, 6 to 8 m from the centre), its right track outside the crater: as
    // thesis_scenario_test's CraterOnOneTrack. Seen from behind and to its right.
    {
      auto terrain = FlatTerrain();
      if (dt::Status s = terrain->Add({1, 1, 1}, dt::FeatureParams::Crater(100, 100, 10)); !s) {
        throw std::runtime_error(s.error().message);
      }
      auto v = dt::SimulatedVehicle::Make(tank, *terrain, 70, 93 - 1.85, 0).value();
      Write(Sequence(renderer, *terrain, v, {{0.0, 4.0, 0.0}}, {2.0, 4.5, 6.0, 7.0, 8.5, 11.0},
                     Eigen::Vector3d(-16.0, 7.0, -12.0)),
            std::filesystem::path(out_dir) / "vehicle-crater.png");
    }

    // A tank driving east onto a 6 m bridge (ramps 30 m, span 40 m, 10 m wide at z 200), then
    // turning left off the span's side at 5 m/s: it falls 6 m and dies (FallOffTheSide...).
    // Seen from the north-west, the side it falls off, from below the deck.
    {
      auto terrain = FlatTerrain();
      if (dt::Status s = terrain->Add(
              {1, 1, 1}, dt::FeatureParams::Bridge(100, 200, 0.0, 10, 30, 40, 30, 6.0, 6.0));
          !s) {
        throw std::runtime_error(s.error().message);
      }
      auto v = dt::SimulatedVehicle::Make(tank, *terrain, 50, 200, 0).value();
      // x > 115 comes about 8.6 s in at 8 m/s (the scenario test waits for it the same way).
      double turn_s = 0.0;
      {
        auto probe = dt::SimulatedVehicle::Make(tank, *terrain, 50, 200, 0).value();
        (void)probe.Command(8.0, 0.0);
        while (probe.pose().x_m <= 115.0) {
          (void)probe.Advance(*terrain, kTickS);
          turn_s += kTickS;
        }
      }
      Write(Sequence(renderer, *terrain, v, {{0.0, 8.0, 0.0}, {turn_s, 5.0, 0.4}},
                     {turn_s - 1.0, turn_s + 2.2, turn_s + 3.0, turn_s + 3.3, turn_s + 3.6,
                      turn_s + 5.5},
                     Eigen::Vector3d(-12.0, 3.0, 24.0)),
            std::filesystem::path(out_dir) / "vehicle-fall.png");
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_vehicle_pictures: %s\n", e.what());
    return 1;
  }
}
