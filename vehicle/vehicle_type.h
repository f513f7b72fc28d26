// VehicleType: the size, speed and survivable-tilt limits of a kind of vehicle.
#pragma once

#include <string>
#include <string_view>

#include "base/result.h"

namespace dt {

// Values are documented in docs/terrain.md "Vehicles". Angles in radians.
struct VehicleType {
  std::string name;
  double length_m = 0.0;               // along the heading
  double width_m = 0.0;                // across the heading
  double max_speed_mps = 0.0;          // forward limit of the commanded speed
  double max_reverse_speed_mps = 0.0;  // backward limit (a positive number)
  double max_turn_rate_rad_s = 0.0;    // limit of the commanded heading rate, either way
  // A vehicle falling off a bridge dies when the tilt of the fall exceeds either limit.
  double max_pitch_rad = 0.0;
  double max_roll_rad = 0.0;

  bool operator==(const VehicleType&) const = default;
};

// Documented maxima: bigger values are refused.
inline constexpr double kMaxVehicleLengthM = 50.0;
inline constexpr double kMaxVehicleWidthM = 20.0;
inline constexpr double kMaxVehicleSpeedMps = 300.0;
inline constexpr double kMaxVehicleTurnRateRadS = 10.0;

// Survivable tilt of every built-in type (docs/terrain.md "Vehicles").
inline constexpr double kDefaultMaxPitchDeg = 35.0;
inline constexpr double kDefaultMaxRollDeg = 30.0;

// Built-in types.
VehicleType TankType();   // "tank": 7.9 x 3.7 m, 18 m/s, 0.7 rad/s
VehicleType TruckType();  // "truck": 6.7 x 2.4 m, 25 m/s, 0.35 rad/s
VehicleType JeepType();   // "jeep": 4.6 x 2.2 m, 30 m/s, 0.8 rad/s
// "bulldozer": 5.9 x 3.7 m (blade included), 3 m/s, 0.6 rad/s; its blade is vehicle/blade.h's.
VehicleType BulldozerType();

// A built-in type by name; the error lists the known names.
Result<VehicleType> BuiltInVehicleType(std::string_view name);

// Finite values inside the documented ranges; the error names the field and its value.
Status ValidateVehicleType(const VehicleType& type);

}  // namespace dt
