// Craters, bridges and berms to DIS object states and back.
#include "dis/feature_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "dis/dis_codec.h"
#include "dis/object_types.h"
#include "terrain/crater.h"

namespace dt::dis {
namespace {

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}
constexpr PduContext kContext{5, 0x100};
constexpr FeatureId kId{3, 4, 17};

// Through the wire as well: what the far end decodes, not just the struct.
ObjectStatePdu ThroughTheWire(const ObjectStatePdu& pdu) {
  const std::vector<uint8_t> bytes = std::visit([](const auto& p) { return Encode(p); }, pdu);
  const DecodeResult r = DecodePdu(bytes, kContext.exercise_id);
  if (!r.ok()) ADD_FAILURE() << r.error().message;
  if (const auto* point = std::get_if<PointObjectStatePdu>(&r.pdu())) return *point;
  return std::get<LinearObjectStatePdu>(r.pdu());
}

TEST(FeatureMapping, CraterIsAPointObjectWithItsAppearance) {
  const FeatureParams crater = FeatureParams::Crater(120.0, 340.0, 10.0);
  const auto pdu = FeatureToDis(kId, crater, 12.5, 7, Frame(), kContext);
  ASSERT_TRUE(pdu.ok()) << pdu.error().message;
  const auto& point = std::get<PointObjectStatePdu>(pdu.value());
  EXPECT_EQ(point.object_type, kCraterObjectType);
  EXPECT_EQ(point.object_id, (EntityId{3, 4, 17}));
  EXPECT_EQ(point.update_number, 7);
  EXPECT_EQ(point.header.exercise_id, 5);
  const CraterAppearance a = UnpackCraterAppearance(point.specific_appearance);
  EXPECT_EQ(a.diameter_m, 20);
  EXPECT_EQ(a.depth_cm, 0);     // a standard crater's rings never go below the bare ground
  EXPECT_EQ(a.height_cm, 150);  // rim at 0.15 x radius
  EXPECT_EQ(point.general_appearance & general_appearance::kPercentCompleteMask, 100);
  const WorldCoordinates expected = Frame().ToGeocentric({120.0, 12.5, 340.0});
  EXPECT_DOUBLE_EQ(point.location.x, expected.x);
  EXPECT_DOUBLE_EQ(point.location.y, expected.y);
  EXPECT_DOUBLE_EQ(point.location.z, expected.z);

  const auto back = FeatureFromDisPdu(ThroughTheWire(pdu.value()), Frame());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(back.value().complete);
  EXPECT_FALSE(back.value().deactivated);
  EXPECT_EQ(back.value().id, kId);
  EXPECT_EQ(back.value().update_number, 7);
  EXPECT_EQ(back.value().params.type, FeatureType::kCrater);
  EXPECT_NEAR(back.value().params.x_m, 120.0, 1e-6);
  EXPECT_NEAR(back.value().params.z_m, 340.0, 1e-6);
  EXPECT_NEAR(back.value().ground_elevation_m, 12.5, 1e-6);
  EXPECT_DOUBLE_EQ(back.value().params.length_m[0], 10.0);
}

TEST(FeatureMapping, CraterAppearanceQuantisesAndSaturates) {
  // Diameter in whole metres: radius 7.3 m -> 15 m -> radius 7.5 m back.
  auto pdu = FeatureToDis(kId, FeatureParams::Crater(0, 0, 7.3), 0, 1, Frame(), kContext);
  ASSERT_TRUE(pdu.ok());
  auto back = FeatureFromDisPdu(pdu.value(), Frame());
  ASSERT_TRUE(back.ok());
  EXPECT_DOUBLE_EQ(back.value().params.length_m[0], 7.5);
  // A 200 m radius crater is 400 m across: the 8-bit diameter saturates at 255 m, and the
  // rim (30 m) at 2.55 m.
  pdu = FeatureToDis(kId, FeatureParams::Crater(0, 0, 200.0), 0, 1, Frame(), kContext);
  ASSERT_TRUE(pdu.ok());
  const CraterAppearance a =
      UnpackCraterAppearance(std::get<PointObjectStatePdu>(pdu.value()).specific_appearance);
  EXPECT_EQ(a.diameter_m, 255);
  EXPECT_EQ(a.height_cm, 255);
}

TEST(FeatureMapping, CraterVertexEditsGiveDepthAndHeight) {
  FeatureParams crater = FeatureParams::Crater(0, 0, 4.0);  // rim 0.6 m
  crater = WithCraterVertexEdit(crater, {3, 0, -0.42});
  crater = WithCraterVertexEdit(crater, {5, 1, 0.9});
  const auto pdu = FeatureToDis(kId, crater, 0, 1, Frame(), kContext);
  ASSERT_TRUE(pdu.ok());
  const CraterAppearance a =
      UnpackCraterAppearance(std::get<PointObjectStatePdu>(pdu.value()).specific_appearance);
  EXPECT_EQ(a.depth_cm, 42);
  EXPECT_EQ(a.height_cm, 90);
}

TEST(FeatureMapping, BermIsALinearObjectOfOneSegment) {
  const FeatureParams berm = FeatureParams::Berm(50.0, 60.0, 0.7, 40.0, 6.0, 2.5);
  const auto pdu = FeatureToDis(kId, berm, 3.0, 2, Frame(), kContext);
  ASSERT_TRUE(pdu.ok()) << pdu.error().message;
  const auto& linear = std::get<LinearObjectStatePdu>(pdu.value());
  EXPECT_EQ(linear.object_type, kBermObjectType);
  ASSERT_EQ(linear.segments.size(), 1u);
  EXPECT_FLOAT_EQ(linear.segments[0].length_m, 40.0f);
  EXPECT_FLOAT_EQ(linear.segments[0].width_m, 6.0f);
  EXPECT_FLOAT_EQ(linear.segments[0].height_m, 2.5f);
  EXPECT_FLOAT_EQ(linear.segments[0].depth_m, 0.0f);

  const auto back = FeatureFromDisPdu(ThroughTheWire(pdu.value()), Frame());
  ASSERT_TRUE(back.ok()) << back.error().message;
  const FeatureParams& p = back.value().params;
  EXPECT_TRUE(back.value().complete);
  EXPECT_EQ(p.type, FeatureType::kBerm);
  EXPECT_NEAR(p.x_m, 50.0, 1e-6);
  EXPECT_NEAR(p.z_m, 60.0, 1e-6);
  EXPECT_NEAR(p.direction_rad, 0.7, 2e-6);
  EXPECT_DOUBLE_EQ(p.length_m[0], 40.0);
  EXPECT_DOUBLE_EQ(p.width_m, 6.0);
  EXPECT_DOUBLE_EQ(p.height_m[0], 2.5);
  EXPECT_NEAR(back.value().ground_elevation_m, 3.0, 1e-6);
}

TEST(FeatureMapping, BridgeIsAPassagewayWhoseDestructionIsItsDamage) {
  FeatureParams bridge = FeatureParams::Bridge(200.0, 210.0, -1.2, 8.0, 20.0, 60.0, 20.0, 5, 5);
  auto pdu = FeatureToDis(kId, bridge, 1.0, 1, Frame(), kContext);
  ASSERT_TRUE(pdu.ok()) << pdu.error().message;
  auto point = std::get<PointObjectStatePdu>(pdu.value());
  EXPECT_EQ(point.object_type, kBridgeObjectType);
  EXPECT_EQ(point.general_appearance & general_appearance::kDamageMask, 0);

  bridge.status = BridgeStatus::kDestroyed;
  pdu = FeatureToDis(kId, bridge, 1.0, 2, Frame(), kContext);
  ASSERT_TRUE(pdu.ok());
  point = std::get<PointObjectStatePdu>(pdu.value());
  EXPECT_EQ((point.general_appearance & general_appearance::kDamageMask) >>
                general_appearance::kDamageShift,
            general_appearance::kDamageDestroyed);
  EXPECT_FALSE(IsDeactivated(pdu.value())) << "a destroyed bridge is still there";

  const auto back = FeatureFromDisPdu(ThroughTheWire(pdu.value()), Frame());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_FALSE(back.value().complete);
  EXPECT_EQ(back.value().params.type, FeatureType::kBridge);
  EXPECT_EQ(back.value().params.status, BridgeStatus::kDestroyed);
  EXPECT_NEAR(back.value().params.direction_rad, -1.2, 2e-6);
  EXPECT_NEAR(back.value().params.x_m, 200.0, 1e-6);
}

TEST(FeatureMapping, RemovalIsTheLastStateDeactivatedWithTheNextUpdateNumber) {
  for (const FeatureParams& params :
       {FeatureParams::Crater(1, 2, 3), FeatureParams::Berm(1, 2, 0, 10, 3, 1)}) {
    const auto pdu = FeatureToDis(kId, params, 0, 9, Frame(), kContext);
    ASSERT_TRUE(pdu.ok());
    EXPECT_FALSE(IsDeactivated(pdu.value()));
    const ObjectStatePdu gone = Deactivated(pdu.value(), 10, {5, 0x200});
    EXPECT_TRUE(IsDeactivated(gone));
    const auto back = FeatureFromDisPdu(ThroughTheWire(gone), Frame());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(back.value().deactivated);
    EXPECT_EQ(back.value().update_number, 10);
    EXPECT_EQ(back.value().params.type, params.type);
  }
}

TEST(FeatureMapping, FeatureNumbersBeyondDisRangeHaveNoObjectId) {
  EXPECT_TRUE(ObjectIdOf({1, 2, kMaxDisObjectNumber}).ok());
  const auto too_big = ObjectIdOf({1, 2, kMaxDisObjectNumber + 1});
  ASSERT_FALSE(too_big.ok());
  EXPECT_NE(too_big.error().message.find("65534"), std::string::npos) << too_big.error().message;
  EXPECT_FALSE(ObjectIdOf({1, 2, 0}).ok());
  const auto pdu =
      FeatureToDis({1, 2, 70000}, FeatureParams::Crater(0, 0, 3), 0, 1, Frame(), kContext);
  EXPECT_FALSE(pdu.ok());
}

TEST(FeatureMapping, ReservedObjectNumbersAreNotFeatures) {
  auto point = std::get<PointObjectStatePdu>(
      FeatureToDis(kId, FeatureParams::Crater(0, 0, 3), 0, 1, Frame(), kContext).value());
  for (uint16_t reserved : {uint16_t{0}, uint16_t{65534}, uint16_t{65535}}) {
    point.object_id.entity = reserved;
    const auto back = FeatureFromDisPdu(point, Frame());
    ASSERT_FALSE(back.ok()) << reserved;
    EXPECT_NE(back.error().message.find(std::to_string(reserved)), std::string::npos);
  }
  point.object_id.entity = 65533;
  EXPECT_TRUE(FeatureFromDisPdu(point, Frame()).ok());
}

TEST(FeatureMapping, InvalidParametersAreMisuse) {
  FeatureParams bad = FeatureParams::Crater(0, 0, 3);
  bad.length_m[0] = std::nan("");
  EXPECT_THROW((void)FeatureToDis(kId, bad, 0, 1, Frame(), kContext), std::invalid_argument);
  EXPECT_THROW(
      (void)FeatureToDis(kId, FeatureParams::Crater(0, 0, 3), INFINITY, 1, Frame(), kContext),
      std::invalid_argument);
}

TEST(FeatureMapping, ForeignObjectsAreNotFeatures) {
  auto pdu = FeatureToDis(kId, FeatureParams::Crater(0, 0, 3), 0, 1, Frame(), kContext);
  ASSERT_TRUE(pdu.ok());
  auto point = std::get<PointObjectStatePdu>(pdu.value());
  point.object_type = {1, 1, 5, 0};  // rut
  auto back = FeatureFromDisPdu(point, Frame());
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.error().message.find("1/1/5/0"), std::string::npos) << back.error().message;
  point.object_type = kCraterObjectType;
  point.specific_appearance = 0;
  EXPECT_FALSE(FeatureFromDisPdu(point, Frame()).ok()) << "a crater of diameter 0";

  auto linear = std::get<LinearObjectStatePdu>(
      FeatureToDis(kId, FeatureParams::Berm(0, 0, 0, 10, 3, 1), 0, 1, Frame(), kContext).value());
  linear.segments.push_back(linear.segments[0]);
  EXPECT_FALSE(FeatureFromDisPdu(linear, Frame()).ok()) << "two segments";
  linear.segments.resize(1);
  linear.segments[0].height_m = 0.0f;
  EXPECT_FALSE(FeatureFromDisPdu(linear, Frame()).ok()) << "a berm of height 0";
  linear.segments[0].height_m = 1.0f;
  linear.object_type = {1, 1, 1, 0};  // tank ditch
  EXPECT_FALSE(FeatureFromDisPdu(linear, Frame()).ok());
}

}  // namespace
}  // namespace dt::dis
