#include "vehicle/bridge_traversal.h"

#include <algorithm>
#include <cmath>

namespace dt {

bool MovingAlong(const Vehicle& vehicle, double direction_rad) {
  if (vehicle.speed_mps() == 0.0) return false;
  return std::abs(WrapAngleRad(vehicle.TravelDirectionRad() - direction_rad)) <=
         kBridgeAlignToleranceRad;
}

BridgeEvent UpdateBridgeTag(std::span<const Bridge* const> nearby, Vehicle& vehicle) {
  BridgeEvent event = BridgeEvent::kNone;
  const double x = vehicle.x_m(), z = vehicle.z_m();
  if (vehicle.on_bridge()) {
    for (const Bridge* b : nearby) {
      if (b->id() != vehicle.bridge() || !b->InOuterHotSpot(x, z)) continue;
      const BridgeHotSpot spot = b->HotSpotAt(x, z);
      // Leaving is getting on in reverse: moving opposite to the way onto the deck.
      if (MovingAlong(vehicle, b->OntoDirectionRad(spot) + std::numbers::pi)) {
        vehicle.clear_bridge();
        event = BridgeEvent::kDroveOff;
      }
    }
  }
  if (!vehicle.on_bridge()) {
    for (const Bridge* b : nearby) {
      const BridgeHotSpot spot = b->HotSpotAt(x, z);
      if (spot == BridgeHotSpot::kNone || !MovingAlong(vehicle, b->OntoDirectionRad(spot))) {
        continue;
      }
      vehicle.set_bridge(b->id());
      return BridgeEvent::kMounted;
    }
  }
  return event;
}

double VehicleSurfaceAt(const Terrain& terrain, std::span<const Bridge* const> nearby,
                        const Bridge* on, GroundPoint p) {
  if (on != nullptr) {
    if (auto deck = on->DeckElevationAt(p.x_m, p.z_m)) return *deck;
    return terrain.ElevationAt(p.x_m, p.z_m);
  }
  double e = terrain.ElevationAt(p.x_m, p.z_m);
  for (const Bridge* b : nearby) {
    if (b->HotSpotAt(p.x_m, p.z_m) == BridgeHotSpot::kNone) continue;
    if (auto deck = b->DeckElevationAt(p.x_m, p.z_m)) e = std::max(e, *deck);
  }
  return e;
}

int UncarriedCorners(const Bridge& bridge, const Vehicle& vehicle) {
  const auto points = vehicle.SixPoints();
  int count = 0;
  for (int k : kCorners) {
    const GroundPoint p = points[k];
    const double along = bridge.ToBridge(p.x_m, p.z_m).along_m;
    if (along <= bridge.start_along_m() || along >= bridge.end_along_m()) continue;
    if (!bridge.DeckElevationAt(p.x_m, p.z_m)) ++count;
  }
  return count;
}

}  // namespace dt
