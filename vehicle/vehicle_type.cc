#include "vehicle/vehicle_type.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace dt {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

VehicleType Make(std::string name, double length_m, double width_m, double max_speed_mps,
                 double max_reverse_speed_mps, double max_turn_rate_rad_s) {
  return VehicleType{std::move(name),
                     length_m,
                     width_m,
                     max_speed_mps,
                     max_reverse_speed_mps,
                     max_turn_rate_rad_s,
                     kDefaultMaxPitchDeg * kDegToRad,
                     kDefaultMaxRollDeg * kDegToRad};
}

Status CheckRange(std::string_view type, std::string_view field, double value, double min,
                  bool min_inclusive, double max) {
  if (!std::isfinite(value)) {
    return Error{fmt::format("vehicle type '{}': {} is not finite ({})", type, field, value)};
  }
  const bool above_min = min_inclusive ? value >= min : value > min;
  if (!above_min || value > max) {
    return Error{fmt::format("vehicle type '{}': {} = {} is outside {}{}, {}]", type, field, value,
                             min_inclusive ? "[" : "(", min, max)};
  }
  return Status::Ok();
}

}  // namespace

// Hull sizes and road speeds of an M1 tank, an M35 truck and an M998 utility vehicle, rounded.
VehicleType TankType() { return Make("tank", 7.9, 3.7, 18.0, 9.0, 0.7); }
// A D7-class tracked dozer with its blade, rounded: 5.9 x 3.7 m, 3 m/s either way.
VehicleType BulldozerType() { return Make("bulldozer", 5.9, 3.7, 3.0, 3.0, 0.6); }
VehicleType TruckType() { return Make("truck", 6.7, 2.4, 25.0, 5.0, 0.35); }
VehicleType JeepType() { return Make("jeep", 4.6, 2.2, 30.0, 6.0, 0.8); }

Result<VehicleType> BuiltInVehicleType(std::string_view name) {
  for (VehicleType t : {TankType(), TruckType(), JeepType(), BulldozerType()}) {
    if (t.name == name) return t;
  }
  return Error{
      fmt::format("unknown vehicle type '{}' (built-in: tank, truck, jeep, bulldozer)", name)};
}

Status ValidateVehicleType(const VehicleType& t) {
  if (t.name.empty()) return Error{"vehicle type has an empty name"};
  const double right_angle = std::numbers::pi / 2.0;
  struct Field {
    std::string_view name;
    double value, min;
    bool min_inclusive;
    double max;
  };
  for (const Field& f :
       {Field{"length_m", t.length_m, 0.0, false, kMaxVehicleLengthM},
        Field{"width_m", t.width_m, 0.0, false, kMaxVehicleWidthM},
        Field{"max_speed_mps", t.max_speed_mps, 0.0, true, kMaxVehicleSpeedMps},
        Field{"max_reverse_speed_mps", t.max_reverse_speed_mps, 0.0, true, kMaxVehicleSpeedMps},
        Field{"max_turn_rate_rad_s", t.max_turn_rate_rad_s, 0.0, true, kMaxVehicleTurnRateRadS},
        Field{"max_pitch_rad", t.max_pitch_rad, 0.0, false, right_angle},
        Field{"max_roll_rad", t.max_roll_rad, 0.0, false, right_angle}}) {
    if (auto s = CheckRange(t.name, f.name, f.value, f.min, f.min_inclusive, f.max); !s) return s;
  }
  return Status::Ok();
}

}  // namespace dt
