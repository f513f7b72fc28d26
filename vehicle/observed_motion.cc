#include "vehicle/observed_motion.h"

namespace dt {

DrPose DrPoseOf(const SimulatedVehicle& vehicle) {
  const VehiclePose p = vehicle.pose();
  return {{p.x_m, p.elevation_m, p.z_m}, p.heading_rad, p.pitch_rad, p.roll_rad};
}

void ObserveVehicle(MotionEstimator& estimator, const SimulatedVehicle& vehicle, double t_s) {
  const DrPose pose = DrPoseOf(vehicle);
  const PhysicalVehicle* body = vehicle.physical();
  if (body == nullptr) {
    estimator.Update(pose, t_s);
    return;
  }
  const Eigen::Vector3d v = body->velocity_mps();
  const Eigen::Vector3d w_body =
      OrientationMatrix(pose.heading_rad, pose.pitch_rad, pose.roll_rad).transpose() *
      body->angular_velocity_rad_s();
  estimator.UpdateWithRates(pose, t_s, {v.x(), v.y(), v.z()}, {w_body.x(), w_body.y(), w_body.z()});
}

}  // namespace dt
