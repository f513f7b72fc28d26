#include "vehicle/vehicle.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include <fmt/format.h>

namespace dt {

double WrapAngleRad(double a) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  a = std::remainder(a, kTwoPi);  // in [-pi, pi]
  if (a <= -std::numbers::pi) a += kTwoPi;
  return a;
}

Vehicle::Vehicle(VehicleType type, double x_m, double z_m, double heading_rad,
                 double terrain_size_x_m, double terrain_size_z_m)
    : type_(std::move(type)),
      x_m_(x_m),
      z_m_(z_m),
      heading_rad_(WrapAngleRad(heading_rad)),
      terrain_size_x_m_(terrain_size_x_m),
      terrain_size_z_m_(terrain_size_z_m) {}

Result<Vehicle> Vehicle::Make(VehicleType type, double x_m, double z_m, double heading_rad,
                              double terrain_size_x_m, double terrain_size_z_m) {
  if (auto s = ValidateVehicleType(type); !s) return s.error();
  for (double size_m : {terrain_size_x_m, terrain_size_z_m}) {
    if (!std::isfinite(size_m) || size_m <= 0.0) {
      return Error{fmt::format("terrain size {} m must be finite and > 0", size_m)};
    }
  }
  if (!std::isfinite(x_m) || !std::isfinite(z_m) || !std::isfinite(heading_rad)) {
    return Error{
        fmt::format("vehicle pose (x {}, z {}, heading {}) is not finite", x_m, z_m, heading_rad)};
  }
  Vehicle v(std::move(type), x_m, z_m, heading_rad, terrain_size_x_m, terrain_size_z_m);
  if (!v.FootprintOnTerrain(x_m, z_m, v.heading_rad_)) {
    return Error{fmt::format(
        "a {} ({} x {} m) at (x {}, z {}) m heading {} rad leaves the terrain [0, {}] x [0, {}] m",
        v.type_.name, v.type_.length_m, v.type_.width_m, x_m, z_m, heading_rad, terrain_size_x_m,
        terrain_size_z_m)};
  }
  return v;
}

double Vehicle::TravelDirectionRad() const {
  return reversing() ? WrapAngleRad(heading_rad_ + std::numbers::pi) : heading_rad_;
}

GroundPoint Vehicle::PointAt(BodyPoint p) const { return ToGround(x_m_, z_m_, heading_rad_, p); }

std::array<GroundPoint, 6> Vehicle::SixPoints() const {
  const auto layout = SixPointLayout(type_.length_m, type_.width_m);
  std::array<GroundPoint, 6> out;
  for (size_t k = 0; k < layout.size(); ++k) out[k] = PointAt(layout[k]);
  return out;
}

bool Vehicle::FootprintOnTerrain(double x_m, double z_m, double heading_rad) const {
  for (int k : kCorners) {
    const GroundPoint p =
        ToGround(x_m, z_m, heading_rad, SixPointLayout(type_.length_m, type_.width_m)[k]);
    if (!(p.x_m >= 0.0 && p.x_m <= terrain_size_x_m_ && p.z_m >= 0.0 &&
          p.z_m <= terrain_size_z_m_)) {
      return false;
    }
  }
  return true;
}

Status Vehicle::Command(double speed_mps, double heading_rate_rad_s) {
  if (!std::isfinite(speed_mps) || !std::isfinite(heading_rate_rad_s)) {
    return Error{fmt::format("command (speed {} m/s, heading rate {} rad/s) is not finite",
                             speed_mps, heading_rate_rad_s)};
  }
  if (!alive_) return Error{fmt::format("the {} is dead and cannot be driven", type_.name)};
  speed_mps_ = std::clamp(speed_mps, -type_.max_reverse_speed_mps, type_.max_speed_mps);
  heading_rate_rad_s_ =
      std::clamp(heading_rate_rad_s, -type_.max_turn_rate_rad_s, type_.max_turn_rate_rad_s);
  return Status::Ok();
}

Status Vehicle::Step(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s < 0.0) {
    return Error{fmt::format("time step {} s must be finite and >= 0", dt_s)};
  }
  if (!alive_) return Status::Ok();
  const double turn_rad = heading_rate_rad_s_ * dt_s;
  const double distance_m = speed_mps_ * dt_s;
  if (!std::isfinite(turn_rad) || !std::isfinite(distance_m)) {
    return Error{fmt::format("time step {} s is too long: the move is not finite", dt_s)};
  }
  bool stopped = false;
  double new_heading = WrapAngleRad(heading_rad_ + turn_rad);
  if (!FootprintOnTerrain(x_m_, z_m_, new_heading)) {
    new_heading = heading_rad_;
    stopped = true;
  }
  // Moving along the mean heading follows the arc closely for the small steps used.
  const double mean_heading =
      stopped ? heading_rad_ : heading_rad_ + WrapAngleRad(new_heading - heading_rad_) / 2.0;
  const double dx = distance_m * std::cos(mean_heading);
  const double dz = distance_m * std::sin(mean_heading);
  // Each corner must stay in [0, size] on its axis: the largest fraction t of the move allowed.
  // The margin keeps rounding in the recomputed corners from putting one just off the terrain.
  constexpr double kMarginM = 1e-6;
  const double lo = kMarginM;
  double t = 1.0;
  const auto layout = SixPointLayout(type_.length_m, type_.width_m);
  for (int k : kCorners) {
    const GroundPoint c = ToGround(x_m_, z_m_, new_heading, layout[k]);
    for (auto [pos, delta, hi] : {std::tuple{c.x_m, dx, terrain_size_x_m_ - kMarginM},
                                  std::tuple{c.z_m, dz, terrain_size_z_m_ - kMarginM}}) {
      if (delta > 0.0 && pos + delta > hi) t = std::min(t, std::max(0.0, (hi - pos) / delta));
      if (delta < 0.0 && pos + delta < lo) t = std::min(t, std::max(0.0, (pos - lo) / -delta));
    }
  }
  if (t < 1.0) stopped = true;
  heading_rad_ = new_heading;
  x_m_ += t * dx;
  z_m_ += t * dz;
  if (stopped) {
    speed_mps_ = 0.0;
    heading_rate_rad_s_ = 0.0;
  }
  return Status::Ok();
}

void Vehicle::Kill() {
  alive_ = false;
  speed_mps_ = 0.0;
  heading_rate_rad_s_ = 0.0;
}

}  // namespace dt
