// Dead reckoning as DIS does it (IEEE 1278.1 Annex E, world coordinates): extrapolating a
// vehicle's last reported state, and estimating the rates an owner reports.
#pragma once

#include <array>

#include <Eigen/Core>

#include "pdu/vehicle_state.h"

namespace dt {

// Where a dead-reckoned vehicle is: location (world, metres) and orientation (radians).
struct DrPose {
  std::array<double, 3> location_m{};
  double heading_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;
};

// The orientation as a rotation matrix whose columns are the body axes (ahead, up, left) in
// world coordinates (docs/vehicles.md "Frames"): heading about up, then pitch about left, then
// roll about ahead.
Eigen::Matrix3d OrientationMatrix(double heading_rad, double pitch_rad, double roll_rad);
// The same, bit for bit, from the angles' cosines and sines (for a caller that has them).
Eigen::Matrix3d OrientationMatrixOfTrig(double cos_heading, double sin_heading, double cos_pitch,
                                        double sin_pitch, double cos_roll, double sin_roll);
// The inverse, for |pitch| < pi/2: heading in (-pi, pi], pitch, roll in (-pi, pi].
void EulerFromMatrix(const Eigen::Matrix3d& r, double& heading_rad, double& pitch_rad,
                     double& roll_rad);

// DIS's rotation of the orientation over dt_s by a constant body angular velocity w:
// R(t) = R0 * (I + sin(|w|t)/|w| [w]x + (1 - cos(|w|t))/|w|^2 [w]x^2), the transpose of
// Annex E's DR matrix applied to the world-to-body matrix.
Eigen::Matrix3d RotateByBodyRate(const Eigen::Matrix3d& r0, const Eigen::Vector3d& w_body_rad_s,
                                 double dt_s);

// The state's pose dt_s seconds after it held, by its own algorithm:
//   static:   P = P0,                     orientation fixed
//   FPW, RPW: P = P0 + V dt               (RPW rotates, FPW does not)
//   RVW, FVW: P = P0 + V dt + A dt^2 / 2  (RVW rotates, FVW does not)
DrPose Extrapolate(const VehicleStateFields& state, double dt_s);
// The same, bit for bit, with the state's orientation matrix given (OrientationMatrix of its
// heading, pitch and roll): for a state extrapolated every tick, whose matrix is made once.
DrPose Extrapolate(const VehicleStateFields& state, const Eigen::Matrix3d& orientation0,
                   double dt_s);

// The location part of Extrapolate alone, bit for bit: where only the position is needed, the
// orientation's rotation and Euler angles are not worth making.
std::array<double, 3> ExtrapolateLocation(const VehicleStateFields& state, double dt_s);

// Distance between two locations (metres) and the angle of the rotation from one orientation to
// the other (radians, 0 .. pi): the errors the thresholds are compared with.
double PositionErrorM(const DrPose& a, const DrPose& b);
double OrientationErrorRad(const DrPose& a, const DrPose& b);

// The constant body angular velocity that turns r_prev into r_now in dt_s (the inverse of
// RotateByBodyRate for rotations under half a turn).
Eigen::Vector3d BodyRateBetween(const Eigen::Matrix3d& r_prev, const Eigen::Matrix3d& r_now,
                                double dt_s);

// An owner's estimate of the rates it reports, from the poses of successive ticks: velocity and
// acceleration by differences, the body angular velocity by BodyRateBetween. The first call
// reports zero rates; acceleration needs three calls. Rates are clamped to the limits validation
// accepts (pdu/validation.h), so a landing's spike cannot make a PDU the sender must refuse.
class MotionEstimator {
 public:
  void Update(const DrPose& pose, double t_s);
  // The same where the model knows its own velocity (world) and body angular velocity: they are
  // taken as they are, and the acceleration is the difference of successive velocities, smoothed
  // over about 0.1 s (a model stepping in fixed steps is sampled at tick times that fall between
  // its steps, which makes single differences jitter).
  void UpdateWithRates(const DrPose& pose, double t_s, const std::array<double, 3>& velocity_mps,
                       const std::array<double, 3>& angular_velocity_body_rad_s);
  const DrPose& pose() const { return pose_; }
  const std::array<double, 3>& velocity_mps() const { return velocity_; }
  const std::array<double, 3>& acceleration_mps2() const { return acceleration_; }
  const std::array<double, 3>& angular_velocity_body_rad_s() const { return omega_; }

 private:
  int samples_ = 0;
  double t_s_ = 0.0;
  double dt_prev_ = 0.0;
  DrPose pose_;
  // OrientationMatrix of pose_ when Update made it (not after UpdateWithRates), so the next
  // Update makes one matrix, not two.
  Eigen::Matrix3d pose_orientation_;
  bool pose_orientation_valid_ = false;
  std::array<double, 3> mid_velocity_{}, velocity_{}, acceleration_{}, omega_{};
};

}  // namespace dt
