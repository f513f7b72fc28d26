// Tests the VehicleState PDU: conversion, the documented entity types, every rejection, the bus.
#include "pdu/vehicle_state.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "pdu/test/sample_pdus.h"
#include "pdu/validation.h"
#include "transport/pdu_bus.h"
#include "transport/transport.h"

namespace dt {
namespace {

std::optional<RejectReason> ReasonFor(const dtpdu::vehicle_state_t& pdu) {
  dtpdu::vehicle_state_t out;
  auto r = DecodeAndValidate(std::span<const uint8_t>(EncodePdu(pdu)), sample::Context(), out);
  if (!r) return std::nullopt;
  EXPECT_FALSE(r->detail.empty());
  return r->reason;
}

TEST(VehicleState, FieldsSurviveThePduAndItsEncodingBitForBit) {
  const VehicleStateFields tank = sample::Tank();
  const auto pdu = sample::VehicleState();
  dtpdu::vehicle_state_t decoded;
  ASSERT_EQ(DecodeAndValidate(std::span<const uint8_t>(EncodePdu(pdu)), sample::Context(), decoded),
            std::nullopt);
  EXPECT_EQ(FromVehicleState(decoded), tank);
  VehicleStateFields odd = tank;
  odd.location_m[1] = -0.0;
  odd.velocity_mps[0] = std::numeric_limits<double>::denorm_min();
  odd.id = {0xFFFF, 0xFFFE, 0xFFFF};
  odd.type.country = 0xFFFF;  // an unknown type still converts
  const auto back = FromVehicleState(ToVehicleState(odd));
  EXPECT_TRUE(std::signbit(back.location_m[1]));
  EXPECT_EQ(back, odd);
}

TEST(VehicleState, IsOneFixedSize) {
  // docs/pdu.md: 181 bytes, 245 with the authentication trailer.
  EXPECT_EQ(EncodePdu(sample::VehicleState()).size(), 181u);
  EXPECT_EQ(EncodePdu(dtpdu::vehicle_state_t{}).size(), 181u);
}

TEST(VehicleState, MarkingIsCutAtElevenCharacters) {
  VehicleStateFields v = sample::Tank();
  v.marking = "ABCDEFGHIJKLMNOP";
  EXPECT_EQ(FromVehicleState(ToVehicleState(v)).marking, "ABCDEFGHIJK");
}

TEST(VehicleState, BuiltInTypesHaveTheirDocumentedSisoTypes) {
  EXPECT_EQ(EntityTypeOfVehicle("tank")->ToString(), "1.1.225.1.1.3.0");
  EXPECT_EQ(EntityTypeOfVehicle("truck")->ToString(), "1.1.225.7.0.0.0");
  EXPECT_EQ(EntityTypeOfVehicle("jeep")->ToString(), "1.1.225.6.0.0.0");
  EXPECT_EQ(EntityTypeOfVehicle("bulldozer")->ToString(), "1.1.225.18.0.0.0");
  EXPECT_EQ(EntityTypeOfVehicle("boat"), std::nullopt);
  for (const char* name : {"tank", "truck", "jeep", "bulldozer"}) {
    EXPECT_EQ(VehicleNameOfEntityType(*EntityTypeOfVehicle(name)), name);
  }
  EXPECT_EQ(VehicleNameOfEntityType({1, 2, 225, 1, 1, 3, 0}), "");
}

TEST(VehicleState, AlgorithmNamesRoundTrip) {
  for (uint8_t raw = 1; raw <= 5; ++raw) {
    const auto a = static_cast<DeadReckoningAlgorithm>(raw);
    EXPECT_EQ(ParseDeadReckoningAlgorithm(DeadReckoningAlgorithmName(a)), a);
  }
  EXPECT_EQ(ParseDeadReckoningAlgorithm("rvb"), std::nullopt);
  EXPECT_FALSE(IsValidDeadReckoningAlgorithm(0));
  EXPECT_FALSE(IsValidDeadReckoningAlgorithm(6));
}

TEST(VehicleState, EveryBadFieldIsRejectedWithItsReason) {
  using R = RejectReason;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* what;
    std::function<void(dtpdu::vehicle_state_t&)> edit;
    R reason;
  };
  const std::vector<Case> cases = {
      {"foreign exercise", [](auto& p) { p.header.exercise_id = 8; }, R::kForeignExercise},
      {"wrong pdu type", [](auto& p) { p.header.pdu_type = 220; }, R::kPduTypeMismatch},
      {"entity 0", [](auto& p) { p.entity_id.entity = 0; }, R::kBadField},
      {"entity 65536", [](auto& p) { p.entity_id.entity = 65536; }, R::kBadField},
      {"force 4", [](auto& p) { p.force_id = 4; }, R::kBadField},
      {"unknown type", [](auto& p) { p.entity_type.category = 99; }, R::kUnknownEntityType},
      {"air domain", [](auto& p) { p.entity_type.domain = 2; }, R::kUnknownEntityType},
      {"NaN location", [=](auto& p) { p.location_m[1] = nan; }, R::kNotFinite},
      {"inf velocity", [=](auto& p) { p.linear_velocity_mps[2] = -inf; }, R::kNotFinite},
      {"NaN heading", [=](auto& p) { p.orientation_rad[0] = nan; }, R::kNotFinite},
      {"NaN acceleration", [=](auto& p) { p.linear_acceleration_mps2[0] = nan; }, R::kNotFinite},
      {"inf rate", [=](auto& p) { p.angular_velocity_rad_s[1] = inf; }, R::kNotFinite},
      {"speed 301", [](auto& p) { p.linear_velocity_mps[0] = 301; }, R::kOutOfRange},
      {"speed 300 diagonal",
       [](auto& p) {
         p.linear_velocity_mps[0] = 250;
         p.linear_velocity_mps[2] = 250;
       },
       R::kOutOfRange},
      {"acceleration", [](auto& p) { p.linear_acceleration_mps2[1] = 201; }, R::kOutOfRange},
      {"angular rate", [](auto& p) { p.angular_velocity_rad_s[1] = -21; }, R::kOutOfRange},
      {"heading", [](auto& p) { p.orientation_rad[0] = 7; }, R::kOutOfRange},
      {"pitch", [](auto& p) { p.orientation_rad[1] = 3.2; }, R::kOutOfRange},
      {"altitude", [](auto& p) { p.location_m[1] = 1e5; }, R::kOutOfRange},
      {"x < 0", [](auto& p) { p.location_m[0] = -0.01; }, R::kOffTerrain},
      {"z > size", [](auto& p) { p.location_m[2] = 1000.01; }, R::kOffTerrain},
      {"appearance bit", [](auto& p) { p.appearance = 1 << 5; }, R::kBadField},
      {"algorithm 0", [](auto& p) { p.dead_reckoning_algorithm = 0; }, R::kBadField},
      {"algorithm 6", [](auto& p) { p.dead_reckoning_algorithm = 6; }, R::kBadField},
      {"charset", [](auto& p) { p.marking_charset = 2; }, R::kBadField},
      {"control char", [](auto& p) { p.marking[0] = 7; }, R::kBadField},
      {"char after NUL", [](auto& p) { p.marking[10] = 'X'; }, R::kBadField},
  };
  for (const auto& c : cases) {
    auto pdu = sample::VehicleState();
    c.edit(pdu);
    EXPECT_EQ(ReasonFor(pdu), c.reason) << c.what;
  }
  // The edges are accepted: a corner of the terrain, 300 m/s, every known appearance bit.
  auto edge = sample::VehicleState();
  edge.location_m[0] = 0.0;
  edge.location_m[2] = sample::kSampleTerrainM;
  edge.linear_velocity_mps[0] = 300;
  edge.linear_velocity_mps[1] = edge.linear_velocity_mps[2] = 0;
  edge.appearance = static_cast<int32_t>(appearance::kKnown);
  EXPECT_EQ(ReasonFor(edge), std::nullopt);
}

TEST(VehicleState, TravelsOverTheBusAndBadOnesAreCountedNeverDelivered) {
  auto transport = MakeTransport("memq://", sample::kSampleExercise);
  auto config = [](NodeAddress local) {
    PduBusConfig c;
    c.exercise_id = sample::kSampleExercise;
    c.local = local;
    c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
    return c;
  };
  PduBus a(*transport, config({1, 2}));
  PduBus b(*transport, config({3, 4}));
  std::vector<VehicleStateFields> got;
  b.Subscribe<dtpdu::vehicle_state_t>(
      [&](const dtpdu::vehicle_state_t& pdu) { got.push_back(FromVehicleState(pdu)); });
  ASSERT_TRUE(a.Publish(sample::VehicleState()).ok());
  auto bad = sample::VehicleState();
  bad.linear_velocity_mps[0] = 1e6;
  EXPECT_FALSE(a.Publish(bad).ok());  // refused by the sender
  // A stranger's PDU with an unknown type reaches the wire, and the receiver drops it.
  auto unknown = sample::VehicleState();
  unknown.entity_type.kind = 9;
  unknown.sender.site = 5;
  unknown.sender.host = 6;
  ASSERT_TRUE(transport->Publish(PduType::kVehicleState, EncodePdu(unknown)).ok());
  ASSERT_TRUE(b.HandleTimeout(0).ok());
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0], sample::Tank());
  EXPECT_EQ(b.rejects().count(RejectReason::kUnknownEntityType), 1u);
  EXPECT_EQ(RejectReasonName(RejectReason::kUnknownEntityType), "unknown_entity_type");
}

}  // namespace
}  // namespace dt
