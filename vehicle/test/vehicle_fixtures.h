// Shared set-up of the vehicle tests: the shipped friction table, built-in types, terrains and a
// driving loop that records what a scenario needs to print and check.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/friction_table.h"
#include "terrain/terrain.h"
#include "vehicle/physical_vehicle.h"

namespace dt::test {

inline const FrictionTable& ShippedFriction() {
  static const FrictionTable table =
      FrictionTable::LoadFile(std::string(DT_SOURCE_DIR) + "/configs/friction.toml");
  return table;
}

inline PhysicalVehicleType PhysType(const char* name) {
  return BuiltInPhysicalType(name, ShippedFriction()).value();
}

// Flat ground at 10 m elevation, 2 m posts, `size` metres a side.
inline std::unique_ptr<Terrain> FlatTerrain(double size_m = 400.0,
                                            Material soil = Material::kGrass) {
  const int posts = static_cast<int>(size_m / 2.0) + 1;
  return std::make_unique<Terrain>(HeightGrid(posts, 2.0, 10.0f, soil));
}

// Ground that is flat at 10 m up to x = 100 m, then climbs along +x at `slope_deg`.
inline std::unique_ptr<Terrain> SlopeTerrain(double slope_deg, Material soil = Material::kGrass) {
  const int n = 201;
  std::vector<float> posts(static_cast<size_t>(n) * n);
  const double grade = std::tan(slope_deg * 3.14159265358979323846 / 180.0);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = 2.0 * i;
      posts[static_cast<size_t>(j) * n + i] =
          static_cast<float>(10.0 + std::max(0.0, x - 100.0) * grade);
    }
  }
  return std::make_unique<Terrain>(HeightGrid(n, 2.0, std::move(posts), soil));
}

inline constexpr double kGround = 10.0;
inline constexpr double kTick = 1.0 / 30.0;

// What a drive recorded, tick by tick.
struct DriveLog {
  double max_pitch_rad = -INFINITY, min_pitch_rad = INFINITY;
  double max_roll_rad = -INFINITY, min_roll_rad = INFINITY;
  double max_elevation_m = -INFINITY, min_elevation_m = INFINITY;
  double max_landing_mps = 0.0;
  int mounted = 0, drove_off = 0, fell_off = 0, blocked_ticks = 0, sliding_ticks = 0;
  std::string cause;
};

// Drives for `seconds` at 30 Hz ticks, re-issuing the command while the vehicle can move, and
// stops early once `stop(v)` holds.
template <typename Stop>
DriveLog Drive(const Terrain& t, PhysicalVehicle& v, double speed_mps, double rate_rad_s,
               double seconds, Stop stop) {
  DriveLog log;
  if (v.mobile()) {
    EXPECT_TRUE(v.Command(speed_mps, rate_rad_s).ok());
  }
  const int ticks = static_cast<int>(std::lround(seconds / kTick));
  for (int i = 0; i < ticks && !stop(v); ++i) {
    Result<PhysicalReport> r = v.Advance(t, kTick);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (!r) break;
    const PhysicalReport& p = r.value();
    log.max_pitch_rad = std::max(log.max_pitch_rad, v.pitch_rad());
    log.min_pitch_rad = std::min(log.min_pitch_rad, v.pitch_rad());
    log.max_roll_rad = std::max(log.max_roll_rad, v.roll_rad());
    log.min_roll_rad = std::min(log.min_roll_rad, v.roll_rad());
    log.max_elevation_m = std::max(log.max_elevation_m, v.elevation_m());
    log.min_elevation_m = std::min(log.min_elevation_m, v.elevation_m());
    log.max_landing_mps = std::max(log.max_landing_mps, p.max_landing_mps);
    log.mounted += p.mounted.number != 0;
    log.drove_off += p.drove_off.number != 0;
    log.fell_off += p.fell_off.number != 0;
    log.blocked_ticks += p.blocked;
    log.sliding_ticks += p.sliding;
    if (!p.cause.empty()) log.cause = p.cause;
  }
  return log;
}

inline DriveLog Drive(const Terrain& t, PhysicalVehicle& v, double speed_mps, double rate_rad_s,
                      double seconds) {
  return Drive(t, v, speed_mps, rate_rad_s, seconds, [](const PhysicalVehicle&) { return false; });
}

inline double Deg(double rad) { return rad * 180.0 / 3.14159265358979323846; }

}  // namespace dt::test
