#include "vehicle/vehicle_traversal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace dt {
namespace {

// The bridges whose grid squares hold the centre or an orientation point, plus the vehicle's own
// bridge, sorted by ID so that the first hot spot found is independent of insertion order.
std::vector<const Bridge*> NearbyBridges(const Terrain& terrain, const Vehicle& vehicle,
                                         std::span<const GroundPoint> points) {
  std::vector<const Bridge*> out;
  auto add = [&](const Feature* f) {
    if (f == nullptr || f->type() != FeatureType::kBridge) return;
    if (const auto* b = dynamic_cast<const Bridge*>(f)) out.push_back(b);
  };
  for (const GroundPoint& p : points) {
    for (const Feature* f : terrain.FeaturesNear(p.x_m, p.z_m)) add(f);
  }
  if (vehicle.on_bridge()) add(terrain.Find(vehicle.bridge()));
  std::sort(out.begin(), out.end(),
            [](const Bridge* a, const Bridge* b) { return a->id() < b->id(); });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

const Bridge* FindBridge(std::span<const Bridge* const> nearby, FeatureId id) {
  for (const Bridge* b : nearby) {
    if (b->id() == id) return b;
  }
  return nullptr;
}

std::array<double, 6> SixHeights(const Terrain& terrain, std::span<const Bridge* const> nearby,
                                 const Bridge* on, const std::array<GroundPoint, 6>& six) {
  std::array<double, 6> h{};
  for (size_t k = 0; k < six.size(); ++k) h[k] = VehicleSurfaceAt(terrain, nearby, on, six[k]);
  return h;
}

// "100 m" for a square terrain, "100 x 60 m" for another.
std::string SizeText(double x_m, double z_m) {
  return x_m == z_m ? fmt::format("{} m", x_m) : fmt::format("{} x {} m", x_m, z_m);
}

// Step keeps the footprint on a terrain of the vehicle's size: this terrain's.
bool PlacedOn(const Vehicle& vehicle, const Terrain& terrain) {
  return vehicle.terrain_size_x_m() == terrain.ground().size_x_m() &&
         vehicle.terrain_size_z_m() == terrain.ground().size_z_m();
}

}  // namespace

Result<TraversalReport> SettleVehicle(const Terrain& terrain, Vehicle& vehicle) {
  const VehicleType& type = vehicle.type();
  if (!PlacedOn(vehicle, terrain)) {
    return Error{fmt::format("the {} was placed on a terrain of {}, not this one of {}", type.name,
                             SizeText(vehicle.terrain_size_x_m(), vehicle.terrain_size_z_m()),
                             SizeText(terrain.ground().size_x_m(), terrain.ground().size_z_m()))};
  }
  const std::array<GroundPoint, 6> six = vehicle.SixPoints();
  const auto two = TwoPointLayout(type.length_m, type.width_m);
  const GroundPoint centre{vehicle.x_m(), vehicle.z_m()};
  const GroundPoint front = vehicle.PointAt(two[0]);
  const GroundPoint right = vehicle.PointAt(two[1]);
  std::vector<GroundPoint> points(six.begin(), six.end());
  points.insert(points.end(), {centre, front, right});
  for (const GroundPoint& p : points) {
    if (!terrain.Contains(p.x_m, p.z_m)) {
      return Error{fmt::format(
          "the {} at (x {}, z {}) m heading {} rad reaches (x {}, z {}) m, off the terrain "
          "[0, {}] x [0, {}] m",
          type.name, vehicle.x_m(), vehicle.z_m(), vehicle.heading_rad(), p.x_m, p.z_m,
          terrain.ground().size_x_m(), terrain.ground().size_z_m())};
    }
  }

  const std::vector<const Bridge*> nearby = NearbyBridges(terrain, vehicle, points);
  TraversalReport report;

  if (!vehicle.alive()) {
    vehicle.clear_bridge();
  } else {
    if (vehicle.on_bridge() && FindBridge(nearby, vehicle.bridge()) == nullptr) {
      // The bridge was removed: nothing carries the vehicle any more.
      vehicle.clear_bridge();
      report.event = BridgeEvent::kFellOff;
    }
    if (const BridgeEvent e = UpdateBridgeTag(nearby, vehicle); e != BridgeEvent::kNone) {
      report.event = e;
    }
    if (const Bridge* on = vehicle.on_bridge() ? FindBridge(nearby, vehicle.bridge()) : nullptr) {
      const bool centre_on = on->OverDeck(centre.x_m, centre.z_m) ||
                             on->HotSpotAt(centre.x_m, centre.z_m) != BridgeHotSpot::kNone;
      if (UncarriedCorners(*on, vehicle) > 1 || !centre_on) {
        const Orientation tilt =
            CornerPlaneTilt(type.length_m, type.width_m, SixHeights(terrain, nearby, on, six));
        report.event = BridgeEvent::kFellOff;
        report.fall_pitch_rad = tilt.pitch_rad;
        report.fall_roll_rad = tilt.roll_rad;
        vehicle.clear_bridge();
        if (std::abs(tilt.pitch_rad) > type.max_pitch_rad ||
            std::abs(tilt.roll_rad) > type.max_roll_rad) {
          vehicle.Kill();
          report.died = true;
        }
      }
    }
  }

  const Bridge* on = vehicle.on_bridge() ? FindBridge(nearby, vehicle.bridge()) : nullptr;
  bool six_point = on != nullptr || !nearby.empty();
  for (size_t k = 0; k < points.size() && !six_point; ++k) {
    six_point = terrain.FeatureBitAt(points[k].x_m, points[k].z_m);
  }
  Orientation o;
  if (six_point) {
    o = SixPointOrientation(type.length_m, type.width_m, SixHeights(terrain, nearby, on, six),
                            vehicle.reversing());
  } else {
    o = TwoPointOrientation(
        type.length_m, type.width_m, terrain.ElevationAt(centre.x_m, centre.z_m),
        terrain.ElevationAt(front.x_m, front.z_m), terrain.ElevationAt(right.x_m, right.z_m));
  }
  vehicle.set_orientation(o);
  report.method = o.method;
  return report;
}

Result<TraversalReport> DriveVehicle(const Terrain& terrain, Vehicle& vehicle, double dt_s) {
  // Step keeps the footprint on a terrain of the vehicle's size: check it is this terrain's first,
  // so that a refused call moves nothing.
  if (!PlacedOn(vehicle, terrain)) return SettleVehicle(terrain, vehicle);
  if (auto s = vehicle.Step(dt_s); !s) return s.error();
  return SettleVehicle(terrain, vehicle);
}

}  // namespace dt
