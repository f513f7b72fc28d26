#include "vehicle/dead_reckoning.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "pdu/validation.h"
#include "vehicle/vehicle_type.h"

namespace dt {

// A vehicle's own top speed must pass every receiver's validation of its VehicleState.
static_assert(kMaxVehicleSpeedMps <= kMaxVehicleStateSpeedMps);
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d s;
  s << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return s;
}

Eigen::Vector3d ToVector(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// Scales v down to at most `limit` in length. A hair under it: scaled to exactly `limit`, the
// length recomputed from the rounded components came out 200.00000000000003 for an acceleration
// limit of 200, and validation refused to send the state.
void Clamp(std::array<double, 3>& v, double limit) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (n > limit) {
    const double scale = limit / n * (1.0 - 1e-12);
    for (double& x : v) x *= scale;
  }
}

}  // namespace

Eigen::Matrix3d OrientationMatrix(double heading_rad, double pitch_rad, double roll_rad) {
  return OrientationMatrixOfTrig(std::cos(heading_rad), std::sin(heading_rad), std::cos(pitch_rad),
                                 std::sin(pitch_rad), std::cos(roll_rad), std::sin(roll_rad));
}

Eigen::Matrix3d OrientationMatrixOfTrig(double ch, double sh, double cp, double sp, double cr,
                                        double sr) {
  const Eigen::Vector3d ahead0(ch, 0, sh), up0(0, 1, 0), left0(-sh, 0, ch);
  const Eigen::Vector3d ahead = cp * ahead0 + sp * up0;
  const Eigen::Vector3d up1 = -sp * ahead0 + cp * up0;
  const Eigen::Vector3d left = cr * left0 + sr * up1;
  const Eigen::Vector3d up = -sr * left0 + cr * up1;
  Eigen::Matrix3d r;
  r.col(0) = ahead;
  r.col(1) = up;
  r.col(2) = left;
  return r;
}

void EulerFromMatrix(const Eigen::Matrix3d& r, double& heading_rad, double& pitch_rad,
                     double& roll_rad) {
  const Eigen::Vector3d ahead = r.col(0), up = r.col(1), left = r.col(2);
  heading_rad = std::atan2(ahead.z(), ahead.x());
  pitch_rad = std::atan2(ahead.y(), std::hypot(ahead.x(), ahead.z()));
  roll_rad = std::atan2(left.y(), up.y());
}

Eigen::Matrix3d RotateByBodyRate(const Eigen::Matrix3d& r0, const Eigen::Vector3d& w_body_rad_s,
                                 double dt_s) {
  const double rate = w_body_rad_s.norm();
  if (rate * std::abs(dt_s) < 1e-15) return r0;
  const double angle = rate * dt_s;
  const Eigen::Matrix3d s = Skew(w_body_rad_s);
  const Eigen::Matrix3d e = Eigen::Matrix3d::Identity() + std::sin(angle) / rate * s +
                            (1.0 - std::cos(angle)) / (rate * rate) * s * s;
  return r0 * e;
}

DrPose Extrapolate(const VehicleStateFields& s, double dt_s) {
  const bool rotates =
      s.algorithm == DeadReckoningAlgorithm::kRpw || s.algorithm == DeadReckoningAlgorithm::kRvw;
  return Extrapolate(s,
                     rotates ? OrientationMatrix(s.heading_rad, s.pitch_rad, s.roll_rad)
                             : Eigen::Matrix3d::Identity(),
                     dt_s);
}

std::array<double, 3> ExtrapolateLocation(const VehicleStateFields& s, double dt_s) {
  using A = DeadReckoningAlgorithm;
  std::array<double, 3> location_m = s.location_m;
  if (s.algorithm == A::kStatic) return location_m;
  const bool accelerates = s.algorithm == A::kRvw || s.algorithm == A::kFvw;
  for (size_t i = 0; i < 3; ++i) {
    location_m[i] += s.velocity_mps[i] * dt_s;
    if (accelerates) location_m[i] += 0.5 * s.acceleration_mps2[i] * dt_s * dt_s;
  }
  return location_m;
}

DrPose Extrapolate(const VehicleStateFields& s, const Eigen::Matrix3d& orientation0, double dt_s) {
  DrPose p;
  p.location_m = ExtrapolateLocation(s, dt_s);
  p.heading_rad = s.heading_rad;
  p.pitch_rad = s.pitch_rad;
  p.roll_rad = s.roll_rad;
  using A = DeadReckoningAlgorithm;
  const bool rotates = s.algorithm == A::kRpw || s.algorithm == A::kRvw;
  if (rotates) {
    const Eigen::Matrix3d r =
        RotateByBodyRate(orientation0, ToVector(s.angular_velocity_body_rad_s), dt_s);
    EulerFromMatrix(r, p.heading_rad, p.pitch_rad, p.roll_rad);
  }
  return p;
}

double PositionErrorM(const DrPose& a, const DrPose& b) {
  return (ToVector(a.location_m) - ToVector(b.location_m)).norm();
}

double OrientationErrorRad(const DrPose& a, const DrPose& b) {
  const Eigen::Matrix3d m = OrientationMatrix(a.heading_rad, a.pitch_rad, a.roll_rad).transpose() *
                            OrientationMatrix(b.heading_rad, b.pitch_rad, b.roll_rad);
  return std::acos(std::clamp((m.trace() - 1.0) / 2.0, -1.0, 1.0));
}

Eigen::Vector3d BodyRateBetween(const Eigen::Matrix3d& r_prev, const Eigen::Matrix3d& r_now,
                                double dt_s) {
  const Eigen::Matrix3d m = r_prev.transpose() * r_now;
  const double angle = std::acos(std::clamp((m.trace() - 1.0) / 2.0, -1.0, 1.0));
  const Eigen::Vector3d v(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
  if (angle < 1e-12 || dt_s <= 0.0) return Eigen::Vector3d::Zero();
  // Near zero sin(angle)/angle -> 1: v / 2 is then the rotation vector itself.
  const double scale = angle < 1e-6 ? 0.5 : angle / (2.0 * std::sin(angle));
  return v * scale / dt_s;
}

void MotionEstimator::Update(const DrPose& pose, double t_s) {
  const double dt = t_s - t_s_;
  const Eigen::Matrix3d orientation =
      OrientationMatrix(pose.heading_rad, pose.pitch_rad, pose.roll_rad);
  if (samples_ > 0 && dt > 0.0) {
    // The difference is the velocity half a tick ago; the acceleration brings it to now.
    std::array<double, 3> v{};
    for (size_t i = 0; i < 3; ++i) v[i] = (pose.location_m[i] - pose_.location_m[i]) / dt;
    if (samples_ > 1) {
      const double span = 0.5 * (dt + dt_prev_);
      for (size_t i = 0; i < 3; ++i) acceleration_[i] = (v[i] - mid_velocity_[i]) / span;
    }
    mid_velocity_ = v;
    for (size_t i = 0; i < 3; ++i) velocity_[i] = v[i] + 0.5 * dt * acceleration_[i];
    dt_prev_ = dt;
    const Eigen::Vector3d w =
        BodyRateBetween(pose_orientation_valid_
                            ? pose_orientation_
                            : OrientationMatrix(pose_.heading_rad, pose_.pitch_rad, pose_.roll_rad),
                        orientation, dt);
    omega_ = {w.x(), w.y(), w.z()};
    Clamp(velocity_, kMaxVehicleSpeedMps);
    Clamp(acceleration_, kMaxVehicleAccelerationMps2);
    Clamp(omega_, kMaxVehicleAngularRateRadS);
  }
  if (samples_ == 0 || dt > 0.0) {
    pose_ = pose;
    pose_orientation_ = orientation;
    pose_orientation_valid_ = true;
    t_s_ = t_s;
    samples_ = std::min(samples_ + 1, 2);
  }
}

void MotionEstimator::UpdateWithRates(const DrPose& pose, double t_s,
                                      const std::array<double, 3>& velocity_mps,
                                      const std::array<double, 3>& angular_velocity_body_rad_s) {
  const double dt = t_s - t_s_;
  if (samples_ > 0 && dt > 0.0) {
    // Exponential smoothing with a time constant of 0.1 s.
    const double alpha = dt / (dt + 0.1);
    for (size_t i = 0; i < 3; ++i) {
      const double a = (velocity_mps[i] - velocity_[i]) / dt;
      acceleration_[i] += alpha * (a - acceleration_[i]);
    }
  }
  if (samples_ == 0 || dt > 0.0) {
    velocity_ = velocity_mps;
    omega_ = angular_velocity_body_rad_s;
    Clamp(velocity_, kMaxVehicleSpeedMps);
    Clamp(acceleration_, kMaxVehicleAccelerationMps2);
    Clamp(omega_, kMaxVehicleAngularRateRadS);
    pose_ = pose;
    pose_orientation_valid_ = false;
    t_s_ = t_s;
    samples_ = std::min(samples_ + 1, 2);
  }
}

}  // namespace dt
