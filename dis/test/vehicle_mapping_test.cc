// Vehicle poses to Entity State PDUs and back, through the wire.
#include "dis/vehicle_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dis/dis_codec.h"

namespace dt::dis {
namespace {

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}

VehiclePose SamplePose() {
  VehiclePose p;
  p.entity_id = {3, 4, 9};
  p.entity_type = {1, 1, 225, 1, 1, 3, 0};
  p.force_id = 1;
  p.marking = "TANK-9";
  p.position_m = {1523.25, 41.5, 2870.75};
  p.attitude = {2.1, 0.05, -0.03};
  p.velocity_mps = {4.0, 0.2, -3.0};
  p.acceleration_mps2 = {0.5, 0.0, -0.25};
  p.angular_velocity_rad_s = {0.01, -0.02, 0.3};
  p.appearance = 0x10;
  p.dead_reckoning = DeadReckoningAlgorithm::kRvw;
  return p;
}

TEST(VehicleMapping, PoseRoundTripsThroughTheWire) {
  const VehiclePose pose = SamplePose();
  const EntityStatePdu pdu = ToEntityState(pose, Frame(), {5, 0x99}).value();
  EXPECT_EQ(pdu.header.exercise_id, 5);
  EXPECT_EQ(pdu.header.timestamp, 0x99u);
  EXPECT_EQ(pdu.dead_reckoning.algorithm, 4);
  const std::vector<uint8_t> bytes = Encode(pdu);
  ASSERT_EQ(bytes.size(), kEntityStateSize);
  const DecodeResult r = DecodePdu(bytes, uint8_t{5});
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto back = FromEntityState(std::get<EntityStatePdu>(r.pdu()), Frame());
  ASSERT_TRUE(back.ok()) << back.error().message;
  const VehiclePose& b = back.value();
  EXPECT_EQ(b.entity_id, pose.entity_id);
  EXPECT_EQ(b.entity_type, pose.entity_type);
  EXPECT_EQ(b.force_id, 1);
  EXPECT_EQ(b.marking, "TANK-9");
  EXPECT_EQ(b.appearance, 0x10u);
  EXPECT_EQ(b.dead_reckoning, DeadReckoningAlgorithm::kRvw);
  EXPECT_NEAR(b.position_m.x_m, pose.position_m.x_m, 1e-3);
  EXPECT_NEAR(b.position_m.y_m, pose.position_m.y_m, 1e-3);
  EXPECT_NEAR(b.position_m.z_m, pose.position_m.z_m, 1e-3);
  EXPECT_NEAR(b.attitude.heading_rad, pose.attitude.heading_rad, 2e-6);
  EXPECT_NEAR(b.attitude.pitch_rad, pose.attitude.pitch_rad, 2e-6);
  EXPECT_NEAR(b.attitude.roll_rad, pose.attitude.roll_rad, 2e-6);
  EXPECT_NEAR(b.velocity_mps.x_m, 4.0, 1e-5);
  EXPECT_NEAR(b.velocity_mps.y_m, 0.2, 1e-5);
  EXPECT_NEAR(b.velocity_mps.z_m, -3.0, 1e-5);
  EXPECT_NEAR(b.acceleration_mps2.z_m, -0.25, 1e-5);
  EXPECT_NEAR(b.angular_velocity_rad_s[2], 0.3, 1e-7);
}

TEST(VehicleMapping, VelocityIsGeocentric) {
  VehiclePose pose = SamplePose();
  pose.velocity_mps = {10.0, 0.0, 0.0};  // 10 m/s east
  const EntityStatePdu pdu = ToEntityState(pose, Frame(), {}).value();
  const WorldCoordinates a = Frame().ToGeocentric({0, 0, 0});
  const WorldCoordinates b = Frame().ToGeocentric({10, 0, 0});
  EXPECT_NEAR(pdu.linear_velocity.x, b.x - a.x, 1e-5);
  EXPECT_NEAR(pdu.linear_velocity.y, b.y - a.y, 1e-5);
  EXPECT_NEAR(pdu.linear_velocity.z, b.z - a.z, 1e-5);
}

// The error names what is wrong, so a gateway's log says which field of which state.
void ExpectRefused(const VehiclePose& pose, const std::string& names) {
  const auto r = ToEntityState(pose, Frame(), {});
  ASSERT_FALSE(r.ok()) << names;
  EXPECT_NE(r.error().message.find(names), std::string::npos) << r.error().message;
}

TEST(VehicleMapping, BadPosesAreRefused) {
  VehiclePose pose = SamplePose();
  pose.position_m.y_m = std::nan("");
  ExpectRefused(pose, "position");
  pose = SamplePose();
  pose.attitude.roll_rad = INFINITY;
  ExpectRefused(pose, "roll");
  pose = SamplePose();
  pose.marking = "TWELVE-CHARS";
  ExpectRefused(pose, "12 characters");
  pose.marking = "tab\there";
  ExpectRefused(pose, "not printable");
  pose.marking = "ELEVEN-CHRS";
  EXPECT_TRUE(ToEntityState(pose, Frame(), {}).ok());
}

// Finite doubles beyond a float's range: refused here, so Encode (which throws on a non-finite
// float) never sees them.
TEST(VehicleMapping, ValuesBeyondTheFloatsAreRefused) {
  VehiclePose pose = SamplePose();
  pose.velocity_mps.x_m = 1e39;
  ExpectRefused(pose, "velocity");
  pose = SamplePose();
  pose.acceleration_mps2.z_m = -1e39;
  ExpectRefused(pose, "acceleration");
  pose = SamplePose();
  pose.angular_velocity_rad_s[1] = 1e39;
  ExpectRefused(pose, "angular velocity");
  pose = SamplePose();
  pose.velocity_mps.x_m = 1e38;  // still a float
  const auto r = ToEntityState(pose, Frame(), {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_NO_THROW(Encode(r.value()));
}

TEST(VehicleMapping, MarkingOfAnotherCharacterSetIsDropped) {
  EntityStatePdu pdu = ToEntityState(SamplePose(), Frame(), {}).value();
  pdu.marking.character_set = 2;
  const auto back = FromEntityState(pdu, Frame());
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value().marking, "");
}

TEST(VehicleMapping, ReservedEntityNumbersAreRefused) {
  EntityStatePdu pdu = ToEntityState(SamplePose(), Frame(), {}).value();
  for (uint16_t reserved : {uint16_t{0}, uint16_t{65534}, uint16_t{65535}}) {
    pdu.entity_id.entity = reserved;
    EXPECT_FALSE(FromEntityState(pdu, Frame()).ok()) << reserved;
  }
  pdu.entity_id.entity = 65533;
  EXPECT_TRUE(FromEntityState(pdu, Frame()).ok());
}

TEST(VehicleMapping, UndefinedDeadReckoningIsRefused) {
  EntityStatePdu pdu = ToEntityState(SamplePose(), Frame(), {}).value();
  pdu.dead_reckoning.algorithm = 12;
  const auto back = FromEntityState(pdu, Frame());
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.error().message.find("12"), std::string::npos);
}

}  // namespace
}  // namespace dt::dis
