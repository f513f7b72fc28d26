// Dead-reckoning extrapolation and the thresholds that make a new Entity State due.
#include "dis/dead_reckoning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dis/vehicle_mapping.h"

namespace dt::dis {
namespace {

constexpr double kPi = std::numbers::pi;

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}

VehiclePose Moving(DeadReckoningAlgorithm algorithm) {
  VehiclePose p;
  p.entity_id = {1, 2, 3};
  p.position_m = {100, 5, 200};
  p.attitude = {0.3, 0.0, 0.0};
  p.velocity_mps = {10 * std::cos(0.3), 0, 10 * std::sin(0.3)};
  p.dead_reckoning = algorithm;
  return p;
}

TEST(DeadReckoning, FpwMovesAtConstantVelocity) {
  const EntityStatePdu pdu = ToEntityState(Moving(DeadReckoningAlgorithm::kFpw), Frame(), {});
  const LocalPoint at = Frame().FromGeocentric(ExtrapolatedLocation(pdu, 2.0));
  EXPECT_NEAR(at.x_m, 100 + 20 * std::cos(0.3), 1e-4);
  EXPECT_NEAR(at.z_m, 200 + 20 * std::sin(0.3), 1e-4);
  EXPECT_NEAR(at.y_m, 5, 1e-4);
}

TEST(DeadReckoning, StaticAndBodyAlgorithmsStayPut) {
  for (auto algorithm : {DeadReckoningAlgorithm::kStatic, DeadReckoningAlgorithm::kRvb}) {
    const EntityStatePdu pdu = ToEntityState(Moving(algorithm), Frame(), {});
    const WorldCoordinates p = ExtrapolatedLocation(pdu, 3.0);
    EXPECT_EQ(p, pdu.location);
  }
}

TEST(DeadReckoning, RvwAddsHalfTheAccelerationSquared) {
  VehiclePose pose = Moving(DeadReckoningAlgorithm::kRvw);
  pose.acceleration_mps2 = {0, 0, 2.0};  // 2 m/s^2 north
  const EntityStatePdu pdu = ToEntityState(pose, Frame(), {});
  const LocalPoint at = Frame().FromGeocentric(ExtrapolatedLocation(pdu, 3.0));
  EXPECT_NEAR(at.z_m, 200 + 30 * std::sin(0.3) + 0.5 * 2.0 * 9.0, 1e-4);
}

TEST(DeadReckoning, RotatingAlgorithmsTurnByTheBodyRate) {
  VehiclePose pose = Moving(DeadReckoningAlgorithm::kRvw);
  // Body z is down: a positive yaw rate about it turns the nose right, i.e. clockwise seen from
  // above, so the terrain heading (counter-clockwise) goes down.
  pose.angular_velocity_rad_s = {0, 0, 0.1};
  const EntityStatePdu pdu = ToEntityState(pose, Frame(), {});
  const LocalAttitude after = Frame().FromDisOrientation(ExtrapolatedOrientation(pdu, 2.0));
  EXPECT_NEAR(after.heading_rad, 0.3 - 0.2, 1e-5);
  EXPECT_NEAR(after.pitch_rad, 0.0, 1e-5);
  EXPECT_NEAR(after.roll_rad, 0.0, 1e-5);
  pose.dead_reckoning = DeadReckoningAlgorithm::kFpw;
  const EntityStatePdu fixed = ToEntityState(pose, Frame(), {});
  EXPECT_EQ(ExtrapolatedOrientation(fixed, 2.0), fixed.orientation);
}

TEST(DeadReckoning, OrientationDifferenceIsTheRotationAngle) {
  const EulerAngles a = Frame().ToDisOrientation({0.3, 0.1, 0.0});
  const EulerAngles b = Frame().ToDisOrientation({0.3 + 0.05, 0.1, 0.0});
  // A heading change at pitch 0.1 rotates about the vertical: the angle is 0.05.
  EXPECT_NEAR(OrientationDifferenceRad(a, b), 0.05, 1e-5);
  EXPECT_NEAR(OrientationDifferenceRad(a, a), 0.0, 1e-3);
}

TEST(DeadReckoning, UpdateDueOnDriftHeartbeatAndChange) {
  const DeadReckoningThresholds t;
  const VehiclePose start = Moving(DeadReckoningAlgorithm::kFpw);
  const EntityStatePdu sent = ToEntityState(start, Frame(), {});
  // Exactly where dead reckoning puts it 1 s later: nothing due.
  VehiclePose later = start;
  later.position_m.x_m += 10 * std::cos(0.3);
  later.position_m.z_m += 10 * std::sin(0.3);
  EXPECT_EQ(UpdateDue(sent, 1.0, ToEntityState(later, Frame(), {}), t), UpdateReason::kNone);
  // 1.5 m off to the side.
  VehiclePose off = later;
  off.position_m.x_m += 1.5 * std::sin(0.3);
  off.position_m.z_m -= 1.5 * std::cos(0.3);
  EXPECT_EQ(UpdateDue(sent, 1.0, ToEntityState(off, Frame(), {}), t), UpdateReason::kPosition);
  // Turned 5 degrees.
  VehiclePose turned = later;
  turned.attitude.heading_rad += 5 * kPi / 180;
  EXPECT_EQ(UpdateDue(sent, 1.0, ToEntityState(turned, Frame(), {}), t),
            UpdateReason::kOrientation);
  // Turned 2 degrees: within the threshold.
  turned.attitude.heading_rad = later.attitude.heading_rad + 2 * kPi / 180;
  EXPECT_EQ(UpdateDue(sent, 1.0, ToEntityState(turned, Frame(), {}), t), UpdateReason::kNone);
  // Five seconds on the predicted track: the heartbeat.
  VehiclePose track = start;
  track.position_m.x_m += 50 * std::cos(0.3);
  track.position_m.z_m += 50 * std::sin(0.3);
  EXPECT_EQ(UpdateDue(sent, 5.0, ToEntityState(track, Frame(), {}), t), UpdateReason::kHeartbeat);
  VehiclePose changed = later;
  changed.appearance = 1;
  EXPECT_EQ(UpdateDue(sent, 1.0, ToEntityState(changed, Frame(), {}), t), UpdateReason::kChange);
}

TEST(DeadReckoning, TimeoutAfter2Point4Heartbeats) {
  const DeadReckoningThresholds t;
  EXPECT_FALSE(TimedOut(11.9, t));
  EXPECT_TRUE(TimedOut(12.1, t));
}

}  // namespace
}  // namespace dt::dis
