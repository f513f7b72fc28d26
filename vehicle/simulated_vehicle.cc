#include "vehicle/simulated_vehicle.h"

#include <cmath>

namespace dt {

std::string_view VehicleModelName(VehicleModel model) {
  return model == VehicleModel::kLight ? "light" : "physical";
}

std::optional<VehicleModel> ParseVehicleModel(std::string_view name) {
  if (name == "physical") return VehicleModel::kPhysical;
  if (name == "light") return VehicleModel::kLight;
  return std::nullopt;
}

Result<SimulatedVehicle> SimulatedVehicle::Make(const PhysicalVehicleType& type,
                                                const Terrain& terrain, double x_m, double z_m,
                                                double heading_rad, VehicleModel model) {
  SimulatedVehicle out(type);
  if (model == VehicleModel::kLight) {
    Result<LightVehicle> v = LightVehicle::Make(type.base, terrain, x_m, z_m, heading_rad);
    if (!v) return v.error();
    out.light_.emplace(std::move(v).value());
  } else {
    Result<PhysicalVehicle> v = PhysicalVehicle::Make(type, terrain, x_m, z_m, heading_rad);
    if (!v) return v.error();
    out.physical_.emplace(std::move(v).value());
  }
  out.pose_ = out.ComputePose();
  return out;
}

Status SimulatedVehicle::Command(double speed_mps, double heading_rate_rad_s) {
  return light_ ? light_->Command(speed_mps, heading_rate_rad_s)
                : physical_->Command(speed_mps, heading_rate_rad_s);
}

double SimulatedVehicle::commanded_speed_mps() const {
  return light_ ? light_->vehicle().speed_mps() : physical_->commanded_speed_mps();
}

double SimulatedVehicle::commanded_rate_rad_s() const {
  return light_ ? light_->vehicle().heading_rate_rad_s() : physical_->commanded_rate_rad_s();
}

Result<VehicleEvents> SimulatedVehicle::Advance(const Terrain& terrain, double dt_s) {
  VehicleEvents e;
  if (light_) {
    Result<LightReport> r = light_->Advance(terrain, dt_s);
    if (!r) return r.error();
    pose_ = ComputePose();
    const LightReport& l = r.value();
    if (l.event == BridgeEvent::kMounted) e.mounted = l.bridge;
    if (l.event == BridgeEvent::kDroveOff) e.drove_off = l.bridge;
    if (l.event == BridgeEvent::kFellOff) e.fell_off = l.bridge;
    e.died = l.traversal.died;
    if (e.died) e.cause = "fell off a bridge tilted past the type's limits";
    return e;
  }
  const bool was_asleep = physical_->asleep();
  Result<PhysicalReport> r = physical_->Advance(terrain, dt_s);
  if (!r) return r.error();
  // Asleep through the whole call (too short to wake and fall asleep again), it did not move.
  if (!was_asleep || !physical_->asleep() || dt_s >= kSleepAfterS) pose_ = ComputePose();
  const PhysicalReport& p = r.value();
  e.mounted = p.mounted;
  e.drove_off = p.drove_off;
  e.fell_off = p.fell_off;
  e.died = p.damage_now == Damage::kDestroyed;
  e.cause = p.cause;
  return e;
}

VehiclePose SimulatedVehicle::ComputePose() const {
  if (light_) {
    const Vehicle& v = light_->vehicle();
    return {v.x_m(),       v.z_m(),      v.elevation_m(), v.heading_rad(),
            v.pitch_rad(), v.roll_rad(), v.speed_mps()};
  }
  // PhysicalVehicle's heading_rad(), pitch_rad(), roll_rad() and speed_mps(), the same bits, with
  // the forward axis rotated once for the three that use it: a pose is taken every tick.
  const PhysicalVehicle& v = *physical_;
  const Eigen::Quaterniond& q = v.orientation();
  const Eigen::Vector3d f = q * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d up = q * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d left = q * Eigen::Vector3d::UnitZ();
  return {v.x_m(),
          v.z_m(),
          v.elevation_m(),
          std::atan2(f.z(), f.x()),
          std::atan2(f.y(), std::hypot(f.x(), f.z())),
          std::atan2(left.y(), up.y()),
          v.velocity_mps().dot(f)};
}

bool SimulatedVehicle::alive() const {
  return light_ ? light_->vehicle().alive() : physical_->alive();
}

Damage SimulatedVehicle::damage() const {
  if (light_) return light_->vehicle().alive() ? Damage::kNone : Damage::kDestroyed;
  return physical_->damage();
}

FeatureId SimulatedVehicle::bridge() const {
  return light_ ? light_->vehicle().bridge() : physical_->bridge();
}

}  // namespace dt
