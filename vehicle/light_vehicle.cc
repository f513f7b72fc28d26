#include "vehicle/light_vehicle.h"

#include "terrain/bridge.h"

namespace dt {

Result<LightVehicle> LightVehicle::Make(const VehicleType& type, const Terrain& terrain, double x_m,
                                        double z_m, double heading_rad) {
  Result<Vehicle> v = Vehicle::Make(type, x_m, z_m, heading_rad, terrain.ground().size_x_m(),
                                    terrain.ground().size_z_m());
  if (!v) return v.error();
  if (Result<TraversalReport> r = SettleVehicle(terrain, v.value()); !r) return r.error();
  return LightVehicle(std::move(v).value());
}

FeatureId LightVehicle::BridgeAtCentre(const Terrain& terrain) const {
  const double x = vehicle_.x_m(), z = vehicle_.z_m();
  FeatureId best;
  for (const Feature* f : terrain.FeaturesNear(x, z)) {
    if (f->type() != FeatureType::kBridge) continue;
    const auto* b = static_cast<const Bridge*>(f);
    if (!b->OverDeck(x, z) && b->HotSpotAt(x, z) == BridgeHotSpot::kNone) continue;
    if (best.number == 0 || b->id() < best) best = b->id();
  }
  return best;
}

Result<LightReport> LightVehicle::Advance(const Terrain& terrain, double dt_s) {
  const FeatureId before = vehicle_.bridge();
  Result<TraversalReport> r = DriveVehicle(terrain, vehicle_, dt_s);
  if (!r) return r.error();
  LightReport out;
  out.traversal = r.value();
  const FeatureId here = BridgeAtCentre(terrain);
  if (fell_from_.number != 0 && here != fell_from_) fell_from_ = FeatureId{};
  switch (out.traversal.event) {
    case BridgeEvent::kFellOff: {
      const FeatureId from = before.number != 0 ? before : here;
      if (from != fell_from_ || from.number == 0) {
        out.event = BridgeEvent::kFellOff;
        out.bridge = from;
      }
      fell_from_ = from;
      break;
    }
    case BridgeEvent::kMounted:
      if (vehicle_.bridge() != fell_from_) {
        out.event = BridgeEvent::kMounted;
        out.bridge = vehicle_.bridge();
      }
      break;
    case BridgeEvent::kDroveOff:
      out.event = BridgeEvent::kDroveOff;
      out.bridge = before;
      break;
    case BridgeEvent::kNone:
      break;
  }
  return out;
}

}  // namespace dt
