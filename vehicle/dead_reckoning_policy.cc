#include "vehicle/dead_reckoning_policy.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace dt {

Status ValidateDeadReckoningThresholds(const DeadReckoningThresholds& t) {
  struct Field {
    const char* name;
    double value, lo, hi;
  };
  for (const Field& f : {Field{"position_threshold_m", t.position_m, 0.01, 1000.0},
                         Field{"orientation_threshold_deg", t.orientation_deg, 0.01, 180.0},
                         Field{"heartbeat_s", t.heartbeat_s, 0.1, 3600.0},
                         Field{"timeout_heartbeats", t.timeout_heartbeats, 1.0, 100.0}}) {
    if (!std::isfinite(f.value) || f.value < f.lo || f.value > f.hi) {
      return Error{fmt::format("{} = {} is outside [{}, {}]", f.name, f.value, f.lo, f.hi)};
    }
  }
  return {};
}

DrPose PoseOf(const VehicleStateFields& s) {
  return {s.location_m, s.heading_rad, s.pitch_rad, s.roll_rad};
}

std::optional<DrPose> DeadReckoningOwner::Believed(double now_s) const {
  if (!last_) return std::nullopt;
  return Extrapolate(*last_, last_orientation_, now_s - last_s_);
}

bool DeadReckoningOwner::Due(const VehicleStateFields& truth, double now_s) const {
  if (!last_) return true;
  if (truth.appearance != last_->appearance || truth.algorithm != last_->algorithm) return true;
  // The margin keeps a heartbeat on the tick it falls on despite rounding of tick times.
  if (now_s - last_s_ >= thresholds_.heartbeat_s - 1e-9) return true;
  const DrPose actual = PoseOf(truth);
  // The position alone first: beyond its threshold the state is due whatever the orientation,
  // whose extrapolation (a rotation, then three atan2) is the dearer half.
  DrPose believed;
  believed.location_m = ExtrapolateLocation(*last_, now_s - last_s_);
  if (dt::PositionErrorM(believed, actual) > thresholds_.position_m) return true;
  believed = *Believed(now_s);
  return OrientationErrorRad(believed, actual) >
         thresholds_.orientation_deg * std::numbers::pi / 180;
}

void DeadReckoningOwner::Sent(const VehicleStateFields& sent, double now_s) {
  Sent(sent, OrientationMatrix(sent.heading_rad, sent.pitch_rad, sent.roll_rad), now_s);
}

void DeadReckoningOwner::Sent(const VehicleStateFields& sent, const Eigen::Matrix3d& orientation,
                              double now_s) {
  last_ = sent;
  last_orientation_ = orientation;
  last_s_ = now_s;
  ++sent_count_;
}

double DeadReckoningOwner::PositionErrorM(const VehicleStateFields& truth, double now_s) const {
  const auto b = Believed(now_s);
  return b ? dt::PositionErrorM(*b, PoseOf(truth)) : 0.0;
}

}  // namespace dt
