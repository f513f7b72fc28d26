// MapActions: NodeActions over a plain map of features, for tests of scenarios and commands.
#pragma once

#include <map>
#include <vector>

#include "runtime/node_actions.h"
#include "terrain/berm_operations.h"
#include "terrain/terrain.h"
#include "vehicle/physical_type.h"
#include "vehicle/shipped_friction.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// Holds features in a map, as a node would in its replica.
class MapActions : public NodeActions {
 public:
  Result<FeatureId> Create(const FeatureParams& p) override {
    if (Status s = ValidateFeatureParams(p); !s) return s.error();
    const FeatureId id{1, 1, ++number};
    features[id] = p;
    return id;
  }
  std::optional<FeatureParams> Params(FeatureId id) const override {
    auto it = features.find(id);
    if (it == features.end()) return std::nullopt;
    return it->second;
  }
  Status Modify(FeatureId id, const FeatureParams& p) override {
    if (!features.count(id)) return Error{"unknown " + id.ToString()};
    features[id] = p;
    return Status::Ok();
  }
  Status Destroy(FeatureId id) override {
    if (features.erase(id) == 0) return Error{"unknown " + id.ToString()};
    return Status::Ok();
  }
  Result<std::vector<FeatureId>> Breach(FeatureId id, double start_m, double width_m) override {
    auto it = features.find(id);
    if (it == features.end()) return Error{"unknown " + id.ToString()};
    auto pieces = BreachBerm(it->second, start_m + width_m / 2, width_m);
    if (!pieces) return pieces.error();
    features.erase(it);
    std::vector<FeatureId> ids;
    for (const FeatureParams& p : pieces.value()) ids.push_back(Create(p).value());
    return ids;
  }
  int vehicle_count() const override { return 1; }
  // One tank (the physical model, as a node's) on a 100 m terrain: the vehicle's own clamping
  // decides what is applied.
  Result<AppliedDrive> Drive(int index, double speed_mps, double rate) override {
    if (Status s = vehicle.Command(speed_mps, rate); !s) return s.error();
    drives.push_back({index, speed_mps, rate});
    return AppliedDrive{vehicle.type().base.name, vehicle.commanded_speed_mps(),
                        vehicle.commanded_rate_rad_s()};
  }

  uint32_t number = 0;
  Terrain terrain{HeightGrid(11, 10.0, 0.0f)};
  SimulatedVehicle vehicle =
      SimulatedVehicle::Make(BuiltInPhysicalType("tank", ShippedFrictionTable()).value(), terrain,
                             50, 50, 0)
          .value();
  std::map<FeatureId, FeatureParams> features;
  struct DriveCall {
    int index;
    double speed_mps, rate;
  };
  std::vector<DriveCall> drives;
};

}  // namespace dt
