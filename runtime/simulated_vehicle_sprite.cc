#include "runtime/simulated_vehicle_sprite.h"

namespace dt {

VehicleSprite SpriteOf(const SimulatedVehicle& vehicle, Rgba colour) {
  const PhysicalVehicleType& type = vehicle.type();
  const VehiclePose pose = vehicle.pose();
  VehicleSprite s;
  s.x_m = pose.x_m;
  s.y_m = pose.elevation_m;
  s.z_m = pose.z_m;
  if (const PhysicalVehicle* p = vehicle.physical()) {
    const Eigen::Vector3d up = p->orientation() * Eigen::Vector3d::UnitY();
    const Eigen::Vector3d base = p->position_m() - (type.cg_height_m - kStaticSagM) * up;
    s.x_m = base.x();
    s.y_m = base.y();
    s.z_m = base.z();
  }
  s.heading_rad = pose.heading_rad;
  s.pitch_rad = pose.pitch_rad;
  s.roll_rad = pose.roll_rad;
  s.length_m = type.base.length_m;
  s.width_m = type.base.width_m;
  s.height_m = type.hull_height_m;
  s.colour = vehicle.alive() ? colour : kDeadVehicleColour;
  return s;
}

}  // namespace dt
