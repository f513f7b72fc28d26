// PhysicalVehicleType: mass, hull, engine, grip and damage limits of a kind of vehicle.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "base/result.h"
#include "terrain/friction_table.h"
#include "terrain/material.h"
#include "vehicle/vehicle_type.h"

namespace dt {

enum class RunningGear : uint8_t { kTracked = 0, kWheeled = 1 };

// Grip of this type on one material: the friction table's pair for the type's traction class,
// and the rolling-resistance coefficient (docs/vehicles.md "Rolling resistance").
struct SoilGrip {
  double static_friction = 0.0;
  double dynamic_friction = 0.0;
  double rolling_resistance = 0.0;
};

// Values of the built-ins are in docs/vehicles.md "Types". The hull is a box: the footprint of
// `base` (length x width) from `clearance_m` above the bottom of the running gear up to
// `hull_height_m`.
struct PhysicalVehicleType {
  VehicleType base;  // name, footprint, speed and turn limits (vehicle/vehicle_type.h)
  RunningGear gear = RunningGear::kTracked;
  double mass_kg = 0.0;
  double hull_height_m = 0.0;      // bottom of the running gear to the roof
  double clearance_m = 0.0;        // bottom of the running gear to the belly
  double cg_height_m = 0.0;        // bottom of the running gear to the centre of mass
  double engine_power_w = 0.0;     // at the running gear
  double min_turn_radius_m = 0.0;  // wheeled: the tightest turn; tracked: 0 (turns in place)
  // Landing: a contact meeting the ground at this normal speed or more immobilises / destroys.
  double land_immobilise_mps = 0.0;
  double land_kill_mps = 0.0;
  // Grip per material (index: Material value; kFromGround unused).
  std::array<SoilGrip, kMaterialCount> grip{};

  // The static-stability angles: past these the centre of mass is outside the support polygon.
  double StaticRollLimitRad() const;
  double StaticPitchLimitRad() const;
};

// Built-in types by name ("tank", "truck", "jeep"), their grip taken from `friction` for the
// traction class the table gives the name. The error lists the known names.
Result<PhysicalVehicleType> BuiltInPhysicalType(std::string_view name,
                                                const FrictionTable& friction);

// Finite values inside documented ranges; the error names the field and its value.
Status ValidatePhysicalType(const PhysicalVehicleType& type);

// Rolling-resistance factor of a material relative to a paved road (1 on asphalt and concrete).
// The friction table says how well a surface grips, not how much it sinks; this says the latter.
double RollingResistanceFactor(Material material);

}  // namespace dt
