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
#include "vehicle/bridge_solids.h"
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

// World points on the surface of the vehicle's box at most `spacing_m` apart: over the footprint,
// from the bottom of the running gear (or, with `from_belly`, from the hull's bottom) to the roof.
inline std::vector<Eigen::Vector3d> BoxPoints(const PhysicalVehicle& v, double spacing_m,
                                              bool from_belly = false) {
  const PhysicalVehicleType& t = v.type();
  const double L = t.base.length_m, W = t.base.width_m;
  const double lo = (from_belly ? t.clearance_m : 0.0) - t.cg_height_m;
  const double hi = t.hull_height_m - t.cg_height_m;
  const int na = static_cast<int>(std::ceil(L / spacing_m)) + 1;
  const int nl = static_cast<int>(std::ceil(W / spacing_m)) + 1;
  const int nh = static_cast<int>(std::ceil((hi - lo) / spacing_m)) + 1;
  const Eigen::Matrix3d r = v.orientation().toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nl; ++j) {
      for (int k = 0; k < nh; ++k) {
        if (i != 0 && i != na - 1 && j != 0 && j != nl - 1 && k != 0 && k != nh - 1) continue;
        const Eigen::Vector3d b(-L / 2 + L * i / (na - 1), lo + (hi - lo) * k / (nh - 1),
                                -W / 2 + W * j / (nl - 1));
        out.push_back(v.position_m() + r * b);
      }
    }
  }
  return out;
}

// How far the lowest point of the vehicle's box is above what lies under it: the ground and
// earthworks, or the top of a bridge solid at most 0.1 m above the point. A wreck at rest on a
// support has this within a few centimetres of zero.
inline double SupportGap(const Terrain& t, const PhysicalVehicle& v) {
  const std::vector<Solid> solids =
      SolidsNear(t, Rect{v.x_m(), v.z_m(), v.x_m(), v.z_m()}.Expanded(15));
  double gap = INFINITY;
  for (const Eigen::Vector3d& p : BoxPoints(v, 0.25)) {
    double under = t.ElevationAt(p.x(), p.z());
    for (const Solid& s : solids) {
      double a = 0, r = 0;
      s.ToLocal(p.x(), p.z(), a, r);
      if (s.InPlan(a, r) && s.TopAt(a) <= p.y() + 0.1) under = std::max(under, s.TopAt(a));
    }
    gap = std::min(gap, p.y() - under);
  }
  return gap;
}

inline double Deg(double rad) { return rad * 180.0 / 3.14159265358979323846; }

}  // namespace dt::test
