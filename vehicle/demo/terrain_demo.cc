// dt_terrain_demo: builds a terrain with a crater, a berm and a bridge, drives vehicles across
// them and prints each vehicle's elevation, pitch and roll track.
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "terrain/random_terrain.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"
#include "vehicle/vehicle.h"
#include "vehicle/vehicle_traversal.h"

namespace dt {
namespace {

struct DemoOptions {
  uint64_t seed = 7;
  double step_s = 0.25;
  int print_every = 4;
};

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

template <typename T>
T Require(Result<T> result, std::string_view what) {
  if (!result) throw std::runtime_error(fmt::format("{}: {}", what, result.error().message));
  return std::move(result).value();
}

void Require(Status status, std::string_view what) {
  if (!status) throw std::runtime_error(fmt::format("{}: {}", what, status.error().message));
}

std::string_view MethodName(OrientationMethod m) {
  return m == OrientationMethod::kTwoPoint ? "2-point" : "6-point";
}

// Drives one vehicle with a constant command for duration_s and prints its track.
void DriveAndPrint(const Terrain& terrain, Vehicle& vehicle, std::string_view name,
                   double speed_mps, double duration_s, const DemoOptions& options) {
  Require(vehicle.Command(speed_mps, 0.0), "command");
  Require(SettleVehicle(terrain, vehicle), "settle");
  fmt::print("\n{} ({}), {:.1f} m/s for {:.0f} s\n", name, vehicle.type().name, speed_mps,
             duration_s);
  fmt::print("{:>6} {:>8} {:>8} {:>9} {:>9} {:>8} {:>8} {:>9} {:>6}\n", "t_s", "x_m", "z_m",
             "ground_m", "elev_m", "pitch_d", "roll_d", "method", "bridge");
  const int steps = static_cast<int>(std::lround(duration_s / options.step_s));
  for (int k = 0; k <= steps; ++k) {
    TraversalReport report{};
    if (k > 0) report = Require(DriveVehicle(terrain, vehicle, options.step_s), "drive");
    if (k % options.print_every == 0 || report.died) {
      fmt::print("{:6.2f} {:8.2f} {:8.2f} {:9.3f} {:9.3f} {:8.2f} {:8.2f} {:>9} {:>6}{}\n",
                 k * options.step_s, vehicle.x_m(), vehicle.z_m(),
                 terrain.GroundElevationAt(vehicle.x_m(), vehicle.z_m()), vehicle.elevation_m(),
                 vehicle.pitch_rad() * kRadToDeg, vehicle.roll_rad() * kRadToDeg,
                 MethodName(report.method), vehicle.on_bridge() ? "on" : "off",
                 vehicle.alive() ? "" : "  (dead)");
    }
    if (!vehicle.alive()) break;
  }
}

int Run(const DemoOptions& options) {
  // 64 x 64 squares of 10 m: a 640 m square of gently rolling ground.
  Terrain terrain(MakeRandomTerrain(
      {.posts_x = 65, .posts_z = 65, .spacing_m = 10.0, .relief_m = 6.0, .seed = options.seed}));
  const NodeAddress self{1, 1};
  auto id = [&](uint32_t n) { return FeatureId{self.site, self.host, n}; };

  Require(terrain.Add(id(1), FeatureParams::Crater(200.0, 100.0, 8.0)), "crater");
  Require(terrain.Add(id(2), FeatureParams::Berm(260.0, 180.0, std::numbers::pi / 2, 40.0, 6.0, 2.0,
                                                 Material::kDirt)),
          "berm");
  Require(terrain.Add(id(3),
                      FeatureParams::Bridge(300.0, 400.0, 0.0, 10.0, 40.0, 60.0, 40.0, 8.0, 8.0)),
          "bridge");
  fmt::print("terrain: {:.0f} m x {:.0f} m, {} features, digest {}\n", terrain.ground().size_x_m(),
             terrain.ground().size_z_m(), terrain.feature_count(), ComputeDigest(terrain).ToHex());

  // A tank crossing the crater on its left track: roll held until the rear passes the rim.
  auto tank = Require(Vehicle::Make(TankType(), 170.0, 97.0, 0.0, terrain.ground().size_x_m(),
                                    terrain.ground().size_z_m()),
                      "tank");
  DriveAndPrint(terrain, tank, "tank over the crater's edge", 5.0, 12.0, options);

  // A truck crossing the berm square on.
  auto truck = Require(Vehicle::Make(TruckType(), 240.0, 200.0, 0.0, terrain.ground().size_x_m(),
                                     terrain.ground().size_z_m()),
                       "truck");
  DriveAndPrint(terrain, truck, "truck over the berm", 4.0, 10.0, options);

  // A jeep driving up ramp 1, over the span and down ramp 2.
  auto jeep = Require(Vehicle::Make(JeepType(), 235.0, 400.0, 0.0, terrain.ground().size_x_m(),
                                    terrain.ground().size_z_m()),
                      "jeep");
  DriveAndPrint(terrain, jeep, "jeep over the bridge", 8.0, 22.0, options);

  // A second jeep driving under the span across the bridge's line: stays on the ground.
  auto under = Require(Vehicle::Make(JeepType(), 330.0, 360.0, std::numbers::pi / 2,
                                     terrain.ground().size_x_m(), terrain.ground().size_z_m()),
                       "jeep under");
  DriveAndPrint(terrain, under, "jeep under the span", 8.0, 10.0, options);
  return 0;
}

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  CLI::App app{"Drive vehicles over a crater, a berm and a bridge and print their tracks."};
  dt::DemoOptions options;
  app.add_option("--seed", options.seed, "random terrain seed")->capture_default_str();
  app.add_option("--step-s", options.step_s, "simulation step (s)")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  app.add_option("--print-every", options.print_every, "print one line every N steps")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return dt::Run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_terrain_demo: %s\n", e.what());
    return 1;
  }
}
