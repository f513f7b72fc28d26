// SimulatedVehicle: a vehicle moved by the model it names, physical (the default) or light.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "base/result.h"
#include "terrain/terrain.h"
#include "vehicle/light_vehicle.h"
#include "vehicle/physical_vehicle.h"

namespace dt {

enum class VehicleModel : uint8_t {
  kPhysical = 0,  // vehicle/physical_vehicle.h
  kLight = 1,     // the thesis's kinematic rules, vehicle/light_vehicle.h
};
std::string_view VehicleModelName(VehicleModel model);  // "physical", "light"
std::optional<VehicleModel> ParseVehicleModel(std::string_view name);

// Where a vehicle is, under either model (docs/conventions.md for the axes and signs).
struct VehiclePose {
  double x_m = 0.0, z_m = 0.0, elevation_m = 0.0;
  double heading_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;
  double speed_mps = 0.0;
};

// One Advance's events, under either model. Each is reported once.
struct VehicleEvents {
  FeatureId mounted, drove_off, fell_off;
  bool died = false;
  std::string cause;  // why it died or was immobilised
};

class SimulatedVehicle {
 public:
  static Result<SimulatedVehicle> Make(const PhysicalVehicleType& type, const Terrain& terrain,
                                       double x_m, double z_m, double heading_rad,
                                       VehicleModel model = VehicleModel::kPhysical);

  VehicleModel model() const { return light_ ? VehicleModel::kLight : VehicleModel::kPhysical; }
  // The type it was made with (the light model moves it by `type().base` alone).
  const PhysicalVehicleType& type() const { return type_; }
  const std::string& type_name() const { return type_.base.name; }
  // Refused for non-finite values and for a vehicle that cannot be driven (destroyed; under the
  // physical model also immobilised); out-of-range values are clamped to the type's limits.
  Status Command(double speed_mps, double heading_rate_rad_s);
  // The demand after clamping: what the last accepted Command set.
  double commanded_speed_mps() const;
  double commanded_rate_rad_s() const;
  Result<VehicleEvents> Advance(const Terrain& terrain, double dt_s);

  // Computed once per Advance (a group's tick asks it of each vehicle three times: steering,
  // observing its motion, sending its state).
  const VehiclePose& pose() const { return pose_; }
  bool alive() const;
  // kNone, kImmobilised or kDestroyed (the light model: kNone or kDestroyed).
  Damage damage() const;
  // "none", "immobilised", "destroyed" (the light model: "none" or "destroyed").
  std::string_view damage_name() const { return DamageName(damage()); }
  FeatureId bridge() const;
  // The model's own state: exactly one is non-null.
  const PhysicalVehicle* physical() const { return physical_ ? &*physical_ : nullptr; }
  const LightVehicle* light() const { return light_ ? &*light_ : nullptr; }

 private:
  explicit SimulatedVehicle(const PhysicalVehicleType& type) : type_(type) {}
  VehiclePose ComputePose() const;
  VehiclePose pose_;
  PhysicalVehicleType type_;
  std::optional<PhysicalVehicle> physical_;
  std::optional<LightVehicle> light_;
};

}  // namespace dt
