// GatewayCore without sockets: what goes out to DIS for the exercise's vehicles and features,
// what comes in from outside DIS, and what is dropped and counted.
#include "dis/gateway_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <vector>

#include "dis/dis_codec.h"
#include "dis/entity_translation.h"
#include "dis/object_types.h"
#include "dis/test/gateway_samples.h"
#include "runtime/vehicle_listing.h"

namespace dt::dis {
namespace {

constexpr NodeAddress kNode{1, 1};
constexpr NodeAddress kGateway = kSampleGateway;

GatewaySettings Settings(bool import_craters = false) {
  GatewaySettings s = SampleSettings(9, 640.0, kNode);
  s.import_craters = import_craters;
  s.members.insert({1, 100});
  return s;
}

VehicleStateFields Tank(double x_m) {
  VehicleStateFields s = SampleTank({1, 1, 3}, x_m, 200.0, 0.7);
  s.algorithm = dt::DeadReckoningAlgorithm::kRvw;
  s.appearance = appearance::kOnBridge;  // the exercise's own bit: never sent to DIS
  return s;
}

struct Harness {
  explicit Harness(bool import_craters = false, bool with_author = false,
                   size_t bundle_max_bytes = 0, size_t heartbeats_per_tick_max = 2000) {
    FeatureAuthor author;
    if (with_author) {
      author.create = [this](const FeatureParams& p) -> Result<FeatureId> {
        created.push_back(p);
        return FeatureId{kGateway.site, kGateway.host, static_cast<uint32_t>(created.size())};
      };
      author.destroy = [this](FeatureId id) {
        destroyed.push_back(id);
        return Status();
      };
    }
    GatewaySettings settings = Settings(import_craters);
    settings.bundle_max_bytes = bundle_max_bytes;
    settings.heartbeats_per_tick_max = heartbeats_per_tick_max;
    core = std::make_unique<GatewayCore>(
        std::move(settings),
        [this](std::span<const uint8_t> d) {
          sent.emplace_back(d.begin(), d.end());
          return true;
        },
        [this](const VehicleStateFields& s) {
          published.push_back(s);
          return Status();
        },
        std::move(author));
  }
  std::vector<Pdu> Take() {
    std::vector<Pdu> out;
    for (const auto& d : sent) {
      DecodeResult r = DecodePdu(d, 9);
      EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
      if (r.ok()) out.push_back(r.pdu());
    }
    sent.clear();
    return out;
  }
  std::vector<std::vector<uint8_t>> sent;
  std::vector<VehicleStateFields> published;
  std::vector<FeatureParams> created;
  std::vector<FeatureId> destroyed;
  std::unique_ptr<GatewayCore> core;
  Terrain terrain{HeightGrid(65, 10.0, 4.0f)};
  std::map<FeatureId, FeatureParams> live;
};

TEST(GatewayCoreTest, VehicleGoesOutAsEntityStateWithDeadReckoningAndHeartbeat) {
  Harness h;
  h.core->OnVehicleState(kNode, Tank(100.0), 10.0);
  std::vector<Pdu> out = h.Take();
  ASSERT_EQ(out.size(), 1u);
  const auto& es = std::get<EntityStatePdu>(out[0]);
  EXPECT_EQ(es.header.exercise_id, 9);
  EXPECT_EQ(es.entity_id, (EntityId{1, 1, 3}));
  EXPECT_EQ(es.dead_reckoning.algorithm, 4);  // RVW
  EXPECT_EQ(es.appearance & appearance::kOnBridge, 0u);
  const WorldCoordinates want = h.core->frame().ToGeocentric({100.0, 12.5, 200.0});
  EXPECT_NEAR(es.location.x, want.x, 1e-6);
  EXPECT_NEAR(es.location.y, want.y, 1e-6);
  EXPECT_NEAR(es.location.z, want.z, 1e-6);
  EXPECT_EQ(std::string(es.marking.characters.data(), 6), "tank-3");

  // Standing still: nothing until the 5 s heartbeat.
  h.core->OnVehicleState(kNode, Tank(100.0), 11.0);
  h.core->Tick(h.live, h.terrain, 14.9);
  EXPECT_TRUE(h.Take().empty());
  h.core->Tick(h.live, h.terrain, 15.1);
  EXPECT_EQ(h.Take().size(), 1u);
  // Moved beyond the 1 m threshold: at once.
  h.core->OnVehicleState(kNode, Tank(101.5), 15.5);
  EXPECT_EQ(h.Take().size(), 1u);
  // Moved within it: not yet.
  h.core->OnVehicleState(kNode, Tank(101.9), 15.6);
  EXPECT_TRUE(h.Take().empty());

  // Its owner removes it: one last Entity State, deactivated.
  VehicleStateFields gone = Tank(101.9);
  gone.appearance |= appearance::kDeactivated;
  h.core->OnVehicleState(kNode, gone, 16.0);
  out = h.Take();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NE(std::get<EntityStatePdu>(out[0]).appearance & appearance::kDeactivated, 0u);
  EXPECT_EQ(h.core->vehicles_out(), 0u);
  EXPECT_EQ(h.core->counters().entity_removals_sent, 1u);
}

// A state with no Entity State (a velocity beyond a float, a location not finite) is dropped and
// counted inside the handler; the vehicle's next good state goes out as its first.
TEST(GatewayCoreTest, StateWithoutEntityStateIsDroppedAndCounted) {
  Harness h;
  VehicleStateFields fast = Tank(100.0);
  fast.velocity_mps = {1e39, 0.0, 0.0};
  EXPECT_NO_THROW(h.core->OnVehicleState(kNode, fast, 10.0));
  VehicleStateFields lost = Tank(100.0);
  lost.location_m[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NO_THROW(h.core->OnVehicleState(kNode, lost, 10.1));
  EXPECT_TRUE(h.Take().empty());
  EXPECT_EQ(h.core->counters().entity_states_unmapped, 2u);
  EXPECT_EQ(h.core->counters().entity_state_sent, 0u);
  EXPECT_NE(h.core->StatusLines().find("dis_entity_states_unmapped 2"), std::string::npos);

  h.core->OnVehicleState(kNode, Tank(100.0), 10.2);
  EXPECT_EQ(h.Take().size(), 1u);
  EXPECT_EQ(h.core->counters().entity_state_sent, 1u);
}

TEST(GatewayCoreTest, SilentVehicleTimesOutAndImportedOnesAreNotSentBack) {
  Harness h;
  h.core->OnVehicleState(kNode, Tank(100.0), 0.0);
  h.core->OnVehicleState(kGateway, Tank(300.0), 0.0);  // the gateway's own import
  EXPECT_EQ(h.core->vehicles_out(), 1u);
  h.core->Tick(h.live, h.terrain, 12.1);  // timeout 5 s x 2.4
  EXPECT_EQ(h.core->vehicles_out(), 0u);
  EXPECT_EQ(h.core->counters().vehicles_timed_out, 1u);
  // A state of the same entity from another sender is a conflict, not a takeover.
  h.core->OnVehicleState(kNode, Tank(100.0), 13.0);
  h.core->OnVehicleState({1, 2}, Tank(150.0), 13.1);
  EXPECT_EQ(h.core->counters().vehicle_conflicts, 1u);
}

EntityStatePdu Outside(double x_m, const GeodeticFrame& frame) {
  VehicleStateFields s = Tank(x_m);
  s.id = {31, 5, 777};
  s.appearance = 0;
  s.velocity_mps = {2.0, 0.0, -1.0};
  EntityStatePdu pdu = EntityStateOfVehicle(s, frame, {9, 0}).value();
  pdu.entity_type = {1, 1, 222, 0, 0, 0, 0};  // a land platform no built-in type is
  pdu.dead_reckoning.algorithm = 8;           // RVB: body axes
  return pdu;
}

TEST(GatewayCoreTest, OutsideEntityStateIsPublishedAsVehicleState) {
  Harness h;
  h.core->OnDatagram(Encode(Outside(250.0, h.core->frame())), 1.0);
  ASSERT_EQ(h.published.size(), 1u);
  const VehicleStateFields& v = h.published[0];
  EXPECT_EQ(v.id, (dt::EntityId{31, 5, 777}));
  EXPECT_NEAR(v.location_m[0], 250.0, 1e-6);
  EXPECT_NEAR(v.location_m[1], 12.5, 1e-6);
  EXPECT_NEAR(v.location_m[2], 200.0, 1e-6);
  EXPECT_NEAR(v.velocity_mps[0], 2.0, 1e-5);
  EXPECT_NEAR(v.velocity_mps[2], -1.0, 1e-5);
  EXPECT_NEAR(v.heading_rad, 0.7, 1e-5);
  EXPECT_EQ(v.algorithm, dt::DeadReckoningAlgorithm::kRvw);  // RVB's world counterpart
  EXPECT_EQ(v.type, *EntityTypeOfVehicle("truck"));          // category 0: a truck
  EXPECT_EQ(h.core->imported_entities(), 1u);

  // The exercise's own entities (the gateway's datagrams looped back) are not imported.
  h.core->OnDatagram(Encode(EntityStateOfVehicle(Tank(100.0), h.core->frame(), {9, 0}).value()),
                     1.1);
  EXPECT_EQ(h.published.size(), 1u);
  EXPECT_EQ(h.core->counters().own_dropped, 1u);
  // Off the terrain: dropped and counted.
  h.core->OnDatagram(Encode(Outside(5000.0, h.core->frame())), 1.2);
  EXPECT_EQ(h.published.size(), 1u);
  EXPECT_EQ(h.core->counters().entities_unmapped, 1u);
}

// On a rectangular terrain an outside entity is bounded by each side on its own axis.
TEST(GatewayCoreTest, ARectangularTerrainBoundsOutsideEntitiesPerAxis) {
  Harness h;
  const GeodeticFrame& frame = h.core->frame();
  const EntityStatePdu at_600_200 = Outside(600.0, frame);  // x 600 m, z 200 m
  EXPECT_TRUE(VehicleOfEntityState(at_600_200, frame, 640.0, 250.0).ok());
  const auto past_north = VehicleOfEntityState(at_600_200, frame, 640.0, 150.0);
  ASSERT_FALSE(past_north.ok());
  EXPECT_NE(past_north.error().message.find("(600.0, 200.0) m is off the 640 x 150 m terrain"),
            std::string::npos)
      << past_north.error().message;
  EXPECT_FALSE(VehicleOfEntityState(at_600_200, frame, 590.0, 250.0).ok());  // past the east
  // The axes are not swapped: a 250 m x 640 m terrain holds (200, 600), not (600, 200).
  EXPECT_FALSE(VehicleOfEntityState(at_600_200, frame, 250.0, 640.0).ok());

  GatewaySettings tall = Settings();
  tall.terrain_size_x_m = 300.0;
  tall.terrain_size_z_m = 1000.0;
  std::vector<VehicleStateFields> published;
  GatewayCore core(
      tall, [](std::span<const uint8_t>) { return true; },
      [&](const VehicleStateFields& s) {
        published.push_back(s);
        return Status();
      },
      FeatureAuthor{});
  core.OnDatagram(Encode(Outside(250.0, core.frame())), 1.0);
  EXPECT_EQ(published.size(), 1u);
  core.OnDatagram(Encode(Outside(350.0, core.frame())), 1.1);
  EXPECT_EQ(published.size(), 1u);
  EXPECT_EQ(core.counters().entities_unmapped, 1u);
}

TEST(GatewayCoreTest, ListsItsVehiclesInTheNodesFormat) {
  Harness h;
  EXPECT_EQ(h.core->VehiclesText(0.0), "");
  VehicleStateFields moving = Tank(100.0);
  moving.velocity_mps = {2.0, 0.0, 0.0};
  moving.algorithm = dt::DeadReckoningAlgorithm::kFpw;
  h.core->OnVehicleState(kNode, moving, 10.0);
  moving.location_m[0] = 101.0;  // where it drove in 0.5 s: as DIS receivers reckon
  h.core->OnVehicleState(kNode, moving, 10.5);
  h.core->OnDatagram(Encode(Outside(250.0, h.core->frame())), 10.5);
  // Read back with the parser the drills use for a node's reply.
  const auto listed = ParseVehicleListing(h.core->VehiclesText(11.0));
  ASSERT_TRUE(listed) << listed.error().message;
  ASSERT_EQ(listed.value().size(), 2u);
  const ListedVehicle& outside = listed.value()[0];
  EXPECT_TRUE(outside.local);  // the gateway owns what it imports
  EXPECT_EQ(outside.entity, "31:5:777");
  EXPECT_EQ(outside.type, "truck");
  EXPECT_EQ(outside.owner, "1:60");
  // Its RVW state (2 m/s east, 1 m/s south) dead reckoned 0.5 s.
  EXPECT_NEAR(outside.x_m, 251.0, 0.01);
  EXPECT_NEAR(outside.z_m, 199.5, 0.01);
  EXPECT_NEAR(outside.speed_mps, std::sqrt(5.0), 0.01);
  const ListedVehicle& tank = listed.value()[1];
  EXPECT_FALSE(tank.local);
  EXPECT_EQ(tank.entity, "1:1:3");
  EXPECT_EQ(tank.type, "tank");
  EXPECT_EQ(tank.owner, "1:1");
  EXPECT_NEAR(tank.x_m, 102.0, 0.01);  // the last state (10.5 s) dead reckoned to 11 s
  EXPECT_NEAR(tank.y_m, 12.5, 0.01);
  EXPECT_NEAR(tank.heading_deg, 0.7 * 180.0 / std::numbers::pi, 0.01);
  EXPECT_NEAR(tank.age_s, 0.5, 1e-9);
  // Sent once at 10 s and dead reckoned by DIS receivers as FPW: where it is.
  EXPECT_NEAR(tank.model_error_m, 0.0, 0.001);
  const std::string text = h.core->VehiclesText(11.0);
  EXPECT_NE(text.find(" updates=2"), std::string::npos) << text;
  EXPECT_NE(text.find(" sent=1"), std::string::npos) << text;
}

TEST(GatewayCoreTest, BadDisInputIsDroppedAndCountedNeverApplied) {
  Harness h;
  const std::vector<uint8_t> good = Encode(Outside(250.0, h.core->frame()));
  std::vector<uint8_t> short_one(good.begin(), good.begin() + 10);
  std::vector<uint8_t> wrong_length = good;
  wrong_length[9] = static_cast<uint8_t>(wrong_length[9] + 1);
  std::vector<uint8_t> unknown_type = good;
  unknown_type[2] = 2;  // Fire
  std::vector<uint8_t> nan = good;
  const uint64_t quiet_nan = 0x7FF8000000000000ull;
  for (int i = 0; i < 8; ++i) nan[48 + i] = static_cast<uint8_t>(quiet_nan >> (56 - 8 * i));
  std::vector<uint8_t> foreign = good;
  foreign[1] = 10;
  for (const auto* d : {&short_one, &wrong_length, &unknown_type, &nan, &foreign}) {
    h.core->OnDatagram(*d, 1.0);
  }
  EXPECT_TRUE(h.published.empty());
  const DecodeCounters& c = h.core->decode_counters();
  EXPECT_EQ(c.rejected_total(), 5u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kTooShort), 1u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kLengthMismatch), 1u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kUnsupportedPduType), 1u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kNonFinite), 1u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kForeignExercise), 1u);
  EXPECT_NE(h.core->StatusLines().find("dis_in_rejected_foreign_exercise 1"), std::string::npos);
  h.core->OnDatagram(good, 2.0);
  EXPECT_EQ(h.published.size(), 1u);
}

// A datagram bundling PDUs (IEEE 1278.2): each imported on its own, a bad one dropped and counted
// without losing the others, a truncated tail refused once.
TEST(GatewayCoreTest, BundledInputIsTakenPduByPdu) {
  Harness h;
  auto outside = [&](uint32_t entity, double x_m) {
    EntityStatePdu pdu = Outside(x_m, h.core->frame());
    pdu.entity_id.entity = static_cast<uint16_t>(entity);
    return Encode(pdu);
  };
  std::vector<uint8_t> bad = outside(2, 260.0);
  bad[2] = 2;  // Fire
  std::vector<uint8_t> datagram;
  for (const auto& pdu : {outside(1, 250.0), bad, outside(3, 270.0), outside(4, 280.0)}) {
    datagram.insert(datagram.end(), pdu.begin(), pdu.end());
  }
  datagram.resize(datagram.size() - 20);  // the last one cut short
  h.core->OnDatagram(datagram, 1.0);
  ASSERT_EQ(h.published.size(), 2u);
  EXPECT_EQ(h.published[0].id.entity, 1u);
  EXPECT_NEAR(h.published[0].location_m[0], 250.0, 1e-6);
  EXPECT_EQ(h.published[1].id.entity, 3u);
  EXPECT_NEAR(h.published[1].location_m[0], 270.0, 1e-6);
  const DecodeCounters& c = h.core->decode_counters();
  EXPECT_EQ(c.entity_state, 2u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kUnsupportedPduType), 1u);
  EXPECT_EQ(c.rejected_for(DecodeFailure::kLengthMismatch), 1u);
  EXPECT_EQ(c.rejected_total(), 2u);
}

// Bundling on: Entity States wait in the bundle until it is full or flushed (Tick flushes too),
// no datagram over the limit, every PDU in one; off, one PDU per datagram.
TEST(GatewayCoreTest, BundledOutputFillsDatagramsUpToTheLimit) {
  constexpr size_t kLimit = 1400;
  Harness h(false, false, kLimit);
  constexpr int kTanks = 20;
  auto tank = [](int i) {
    VehicleStateFields s = Tank(100.0 + i);
    s.id.entity = static_cast<uint16_t>(100 + i);
    return s;
  };
  for (int i = 0; i < kTanks; ++i) h.core->OnVehicleState(kNode, tank(i), 10.0);
  const size_t per_datagram = kLimit / kEntityStateSize;  // 9
  EXPECT_EQ(h.sent.size(), kTanks / per_datagram) << "only full bundles leave before a flush";
  h.core->Flush();
  h.core->Flush();  // nothing left: no empty datagram
  ASSERT_EQ(h.sent.size(), (kTanks + per_datagram - 1) / per_datagram);
  std::set<uint16_t> entities;
  Decoder d(9);
  for (const auto& datagram : h.sent) {
    EXPECT_LE(datagram.size(), kLimit);
    d.DecodeBundle(datagram, [&](const DecodeResult& r) {
      ASSERT_TRUE(r.ok()) << r.error().message;
      entities.insert(std::get<EntityStatePdu>(r.pdu()).entity_id.entity);
    });
  }
  EXPECT_EQ(entities.size(), static_cast<size_t>(kTanks));
  EXPECT_EQ(d.counters().rejected_total(), 0u);
  EXPECT_EQ(h.core->counters().entity_state_sent, static_cast<uint64_t>(kTanks));
  EXPECT_EQ(h.core->counters().datagrams_sent, h.sent.size());
  EXPECT_NE(h.core->StatusLines().find("dis_datagrams_sent 3"), std::string::npos);
  // A heartbeat from Tick leaves within the same Tick.
  h.sent.clear();
  h.core->Tick(h.live, h.terrain, 15.5);
  EXPECT_EQ(h.sent.size(), (kTanks + per_datagram - 1) / per_datagram);

  Harness off;
  for (int i = 0; i < 3; ++i) off.core->OnVehicleState(kNode, tank(i), 10.0);
  EXPECT_EQ(off.sent.size(), 3u);
  for (const auto& datagram : off.sent) EXPECT_EQ(datagram.size(), kEntityStateSize);
}

// A refused bundle counts each of its PDUs as a failed send.
TEST(GatewayCoreTest, ARefusedBundleCountsEveryPduFailed) {
  GatewaySettings settings = Settings();
  settings.bundle_max_bytes = 1400;
  GatewayCore core(
      settings, [](std::span<const uint8_t>) { return false; },
      [](const VehicleStateFields&) { return Status(); });
  for (int i = 0; i < 4; ++i) {
    VehicleStateFields s = Tank(100.0);
    s.id.entity = static_cast<uint16_t>(100 + i);
    core.OnVehicleState(kNode, s, 10.0);
  }
  EXPECT_EQ(core.counters().send_failed, 0u);
  core.Flush();
  EXPECT_EQ(core.counters().send_failed, 4u);
  EXPECT_EQ(core.counters().datagrams_sent, 0u);
}

TEST(GatewayCoreTest, FeaturesGoOutWithUpdateNumbersPeriodsAndRemoval) {
  Harness h;
  const FeatureId crater{1, 1, 4}, berm{1, 1, 5};
  h.live[crater] = FeatureParams::Crater(100.0, 120.0, 6.0);
  h.live[berm] = FeatureParams::Berm(300.0, 300.0, 0.5, 40.0, 4.0, 2.0);
  h.core->Tick(h.live, h.terrain, 0.0);
  std::vector<Pdu> out = h.Take();
  ASSERT_EQ(out.size(), 2u);
  const auto& point = std::get<PointObjectStatePdu>(out[0]);
  EXPECT_EQ(point.object_id, (EntityId{1, 1, 4}));
  EXPECT_EQ(point.object_type, kCraterObjectType);
  EXPECT_EQ(point.update_number, 1);
  const LocalPoint at = h.core->frame().FromGeocentric(point.location);
  EXPECT_NEAR(at.y_m, 4.0, 1e-6);  // on the bare ground
  EXPECT_EQ(std::get<LinearObjectStatePdu>(out[1]).update_number, 1);

  h.core->Tick(h.live, h.terrain, 4.9);
  EXPECT_TRUE(h.Take().empty());
  h.core->Tick(h.live, h.terrain, 5.0);  // the period: the same state, the same number
  out = h.Take();
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(std::get<PointObjectStatePdu>(out[0]).update_number, 1);

  h.live[crater] = FeatureParams::Crater(100.0, 120.0, 8.0);  // changed: at once
  h.core->Tick(h.live, h.terrain, 5.5);
  out = h.Take();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<PointObjectStatePdu>(out[0]).update_number, 2);
  EXPECT_EQ(
      UnpackCraterAppearance(std::get<PointObjectStatePdu>(out[0]).specific_appearance).diameter_m,
      16);

  h.live.erase(crater);  // destroyed: deactivated now, and twice more a period apart
  h.core->Tick(h.live, h.terrain, 6.0);
  out = h.Take();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(IsDeactivated(ObjectStatePdu(std::get<PointObjectStatePdu>(out[0]))));
  EXPECT_EQ(std::get<PointObjectStatePdu>(out[0]).update_number, 3);
  int removals = 1;
  for (double t = 6.5; t < 30.0; t += 0.5) {
    h.core->Tick(h.live, h.terrain, t);
    for (const Pdu& p : h.Take()) {
      if (const auto* pt = std::get_if<PointObjectStatePdu>(&p)) {
        EXPECT_TRUE(IsDeactivated(ObjectStatePdu(*pt)));
        EXPECT_EQ(pt->update_number, 3);  // resent, not a new transition
        ++removals;
      }
    }
  }
  EXPECT_EQ(removals, 3);
  EXPECT_EQ(h.core->features_out(), 1u);
}

TEST(GatewayCoreTest, UpdatesAloneDriveSendsAndHeartbeatsAreCappedOldestFirst) {
  Harness h(false, false, 0, /*heartbeats_per_tick_max=*/2);
  std::vector<GatewayCore::FeatureUpdate> updates;
  for (uint32_t n = 1; n <= 5; ++n) {
    updates.push_back({FeatureId{1, 1, n}, FeatureParams::Crater(100.0 + 20 * n, 120.0, 6.0)});
  }
  h.core->Tick(updates, h.terrain, 0.0);
  EXPECT_EQ(h.Take().size(), 5u);
  const std::vector<GatewayCore::FeatureUpdate> none;
  h.core->Tick(none, h.terrain, 4.9);
  EXPECT_TRUE(h.Take().empty());
  // Due at 5 s with no update naming them: two a tick, in the order they were sent.
  std::vector<uint32_t> resent;
  for (double t : {5.0, 5.1, 5.2}) {
    h.core->Tick(none, h.terrain, t);
    const std::vector<Pdu> out = h.Take();
    EXPECT_LE(out.size(), 2u) << "at " << t;
    for (const Pdu& p : out) {
      const auto& point = std::get<PointObjectStatePdu>(p);
      EXPECT_EQ(point.update_number, 1);
      resent.push_back(point.object_id.entity);
    }
  }
  EXPECT_EQ(resent, (std::vector<uint32_t>{1, 2, 3, 4, 5}));
  // Gone: deactivated once and no longer resent; the others' next heartbeat keeps its period.
  h.core->Tick(std::vector<GatewayCore::FeatureUpdate>{{FeatureId{1, 1, 1}, std::nullopt}},
               h.terrain, 6.0);
  std::vector<Pdu> out = h.Take();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(IsDeactivated(ObjectStatePdu(std::get<PointObjectStatePdu>(out[0]))));
  EXPECT_EQ(h.core->features_out(), 4u);
}

PointObjectStatePdu OutsideCrater(const GeodeticFrame& frame, bool deactivated) {
  auto pdu = std::get<PointObjectStatePdu>(
      FeatureToDis({40, 2, 9}, FeatureParams::Crater(200.0, 220.0, 5.0), 4.0, 1, frame, {9, 0})
          .value());
  if (deactivated) pdu.general_appearance |= general_appearance::kDeactivated;
  return pdu;
}

TEST(GatewayCoreTest, OutsideCratersAreImportedOnlyWhenAllowed) {
  Harness off;
  off.core->OnDatagram(Encode(OutsideCrater(off.core->frame(), false)), 1.0);
  EXPECT_EQ(off.core->counters().objects_ignored, 1u);

  Harness on(/*import_craters=*/true, /*with_author=*/true);
  on.core->OnDatagram(Encode(OutsideCrater(on.core->frame(), false)), 1.0);
  on.core->OnDatagram(Encode(OutsideCrater(on.core->frame(), false)), 2.0);  // heartbeat
  ASSERT_EQ(on.created.size(), 1u);
  EXPECT_EQ(on.created[0].type, FeatureType::kCrater);
  EXPECT_NEAR(on.created[0].x_m, 200.0, 1e-6);
  EXPECT_NEAR(on.created[0].z_m, 220.0, 1e-6);
  EXPECT_NEAR(on.created[0].length_m[0], 5.0, 1e-9);
  // The imported crater is the gateway's feature: not sent back to DIS.
  on.live[FeatureId{kGateway.site, kGateway.host, 1}] = on.created[0];
  on.core->Tick(on.live, on.terrain, 2.5);
  EXPECT_TRUE(on.Take().empty());
  on.core->OnDatagram(Encode(OutsideCrater(on.core->frame(), true)), 3.0);
  ASSERT_EQ(on.destroyed.size(), 1u);
  EXPECT_EQ(on.destroyed[0], (FeatureId{kGateway.site, kGateway.host, 1}));
  EXPECT_EQ(on.core->counters().craters_removed, 1u);
}

}  // namespace
}  // namespace dt::dis
