// DeadReckoningPolicy: the exercise's dead-reckoning thresholds, and when an owner must send a
// vehicle's state (docs/vehicles.md "Shared vehicles").
#pragma once

#include <optional>

#include "base/result.h"
#include "pdu/vehicle_state.h"
#include "vehicle/dead_reckoning.h"

namespace dt {

// The exercise file's [vehicles] thresholds (DIS's usual defaults).
struct DeadReckoningThresholds {
  double position_m = 1.0;          // send when the dead-reckoned copy is off by more
  double orientation_deg = 3.0;     // ... or turned away by more
  double heartbeat_s = 5.0;         // send at least this often
  double timeout_heartbeats = 2.4;  // receivers drop an entity not heard for this many
  DeadReckoningAlgorithm algorithm = DeadReckoningAlgorithm::kRvw;  // what owners send
  double timeout_s() const { return heartbeat_s * timeout_heartbeats; }
};
// Positive finite values (position 0.01 .. 1000 m, orientation 0.01 .. 180 degrees, heartbeat
// 0.1 .. 3600 s, timeout 1 .. 100 heartbeats); the error names the field and its value.
Status ValidateDeadReckoningThresholds(const DeadReckoningThresholds& t);

// One owned vehicle's sending state: what its receivers believe (the last state sent, dead
// reckoned), so the owner sends only when they would be wrong.
class DeadReckoningOwner {
 public:
  explicit DeadReckoningOwner(DeadReckoningThresholds thresholds) : thresholds_(thresholds) {}

  // True when `truth` at now_s must be sent: nothing was sent yet, the receivers' copy is off by
  // more than a threshold, the appearance changed, or a heartbeat has passed.
  bool Due(const VehicleStateFields& truth, double now_s) const;
  // Records that `sent` was sent at now_s.
  void Sent(const VehicleStateFields& sent, double now_s);
  // The same with OrientationMatrix(sent's heading, pitch, roll) given, bit for bit.
  void Sent(const VehicleStateFields& sent, const Eigen::Matrix3d& orientation, double now_s);
  // The receivers' copy at now_s (nullopt before the first send), and its error against truth.
  std::optional<DrPose> Believed(double now_s) const;
  double PositionErrorM(const VehicleStateFields& truth, double now_s) const;
  uint64_t sent_count() const { return sent_count_; }

 private:
  DeadReckoningThresholds thresholds_;
  std::optional<VehicleStateFields> last_;
  Eigen::Matrix3d last_orientation_;  // OrientationMatrix of last_, made once per state sent
  double last_s_ = 0.0;
  uint64_t sent_count_ = 0;
};

// The pose of a state as DrPose (no extrapolation).
DrPose PoseOf(const VehicleStateFields& s);

}  // namespace dt
