// Tests the JSON the live view's page receives (view/view_model.h): a snapshot holds every live
// feature with its history; a delta holds exactly what changed, and nothing when nothing did.
#include <gtest/gtest.h>

#include <numbers>

#include "engine/test/replica_test_config.h"
#include "vehicle/bridge_solids.h"
#include "view/vehicle_frame.h"
#include "view/view_model.h"

namespace dt {
namespace {

using testing::kTestA;
using testing::kTestB;
using testing::kTestServer;
const NodeAddress kView{1, 50};

class ViewModelTest : public ::testing::Test, public testing::ServerAndTwoNodes {
 protected:
  ViewModelTest() : ServerAndTwoNodes(7, Config()) {}
  static ReplicaConfig Config() {
    ReplicaConfig c = testing::TestReplicaConfig();
    c.members = {{kTestServer, NodeRole::kServer},
                 {kTestA, NodeRole::kNode},
                 {kTestB, NodeRole::kNode},
                 {kView, NodeRole::kObserver}};
    return c;
  }
  Replica& View() { return cluster_.at(kView); }
  MemberNames Names() const {
    return {{kTestA, "node-a"}, {kTestB, "node-b"}, {kTestServer, "server"}};
  }
};

TEST_F(ViewModelTest, ALateSnapshotHoldsEveryLiveFeatureWithItsHistory) {
  auto crater = A().Create(FeatureParams::Crater(30, 30, 3));
  auto berm = B().Create(FeatureParams::Berm(80, 80, 0.0, 30, 3, 2));
  ASSERT_TRUE(crater.ok() && berm.ok());
  cluster_.Run(300);
  ASSERT_TRUE(A().Modify(crater.value(), FeatureParams::Crater(30, 30, 5)).ok());
  cluster_.Run(300);
  cluster_.Start(kView, NodeRole::kObserver);
  cluster_.Run(1500);
  ViewModel model(View(), Names());
  ASSERT_FALSE(model.Update(1000, {}, {}, 1).is_null());
  const nlohmann::json s = model.Snapshot(2000);
  EXPECT_EQ(s["type"], "snapshot");
  ASSERT_EQ(s["features"].size(), 2u);
  const nlohmann::json& c =
      s["features"][0]["id"] == crater.value().ToString() ? s["features"][0] : s["features"][1];
  EXPECT_EQ(c["type"], "crater");
  EXPECT_DOUBLE_EQ(c["radius"].get<double>(), 5.0);
  ASSERT_EQ(c["history"].size(), 2u);
  EXPECT_EQ(c["history"][0]["kind"], "create");
  EXPECT_EQ(c["history"][0]["by"], "node-a");
  EXPECT_EQ(c["history"][1]["kind"], "update");
  EXPECT_EQ(s["events"].size(), 3u);
  EXPECT_EQ(s["relief"], 1);
}

// A page opening takes the copy under the publish lock and writes the text after it: the copy is
// the model as it was, whatever the loop's ticks change meanwhile, and the text is the snapshot.
TEST_F(ViewModelTest, ASnapshotCopyIsTheModelWhenItWasTaken) {
  auto crater = A().Create(FeatureParams::Crater(30, 30, 3));
  ASSERT_TRUE(crater.ok());
  cluster_.Start(kView, NodeRole::kObserver);
  cluster_.Run(1500);
  ViewModel model(View(), Names());
  ASSERT_FALSE(
      model.Update(1000, {}, {{"node-a/0", "node-a", "tank", 1, 2, 0, 0, true}}, 1).is_null());
  const SnapshotCopy copy = model.Copy();
  ASSERT_TRUE(A().Modify(crater.value(), FeatureParams::Crater(30, 30, 6)).ok());
  cluster_.Run(300);
  ASSERT_FALSE(model.Update(1300, {}, {}, 2).is_null());

  const nlohmann::json then =
      nlohmann::json::parse(copy.Text(1400, {{"exercise", {{"name", "x"}}}}));
  EXPECT_EQ(then["type"], "snapshot");
  EXPECT_EQ(then["t_ms"], 1400);
  EXPECT_EQ(then["exercise"]["name"], "x");
  ASSERT_EQ(then["features"].size(), 1u);
  EXPECT_DOUBLE_EQ(then["features"][0]["radius"].get<double>(), 3.0);
  EXPECT_EQ(then["features"][0]["history"].size(), 1u);
  EXPECT_EQ(then["vehicles"].size(), 1u);
  EXPECT_EQ(then["relief"], 1);
  EXPECT_LT(then["seq"].get<uint64_t>(), model.seq());

  const nlohmann::json now = model.Snapshot(1500);
  EXPECT_DOUBLE_EQ(now["features"][0]["radius"].get<double>(), 6.0);
  EXPECT_EQ(now["features"][0]["history"].size(), 2u);
  EXPECT_EQ(now["vehicles"].size(), 0u);
  EXPECT_EQ(now["relief"], 2);
  EXPECT_EQ(now["seq"], model.seq());
}

TEST_F(ViewModelTest, ADeltaHoldsWhatChangedAndNothingWhenNothingDid) {
  cluster_.Start(kView, NodeRole::kObserver);
  cluster_.Run(500);
  ViewModel model(View(), Names());
  (void)model.Update(1, {}, {}, 1);
  EXPECT_TRUE(model.Update(2, {}, {}, 1).is_null());
  auto berm = A().Create(FeatureParams::Berm(60, 60, 0.0, 40, 3, 2));
  ASSERT_TRUE(berm.ok());
  cluster_.Run(300);
  nlohmann::json d = model.Update(3, {}, {}, 1);
  ASSERT_FALSE(d.is_null());
  EXPECT_EQ(d["type"], "delta");
  EXPECT_EQ(d["t_ms"], 3);
  ASSERT_EQ(d["features"].size(), 1u);
  EXPECT_EQ(d["features"][0]["id"], berm.value().ToString());
  EXPECT_FALSE(d.contains("removed"));
  auto pieces = B().Breach(berm.value(), 10, 5);
  ASSERT_TRUE(pieces.ok());
  cluster_.Run(300);
  d = model.Update(4, {}, {}, 1);
  ASSERT_EQ(d["removed"].size(), 1u);
  EXPECT_EQ(d["removed"][0], berm.value().ToString());
  EXPECT_EQ(d["features"].size(), pieces.value().size());
  size_t breaches = 0;
  for (const auto& e : d["events"]) breaches += e["kind"] == "breach" ? 1 : 0;
  EXPECT_EQ(breaches, pieces.value().size());
  EXPECT_EQ(model.feature_count(), pieces.value().size());
  EXPECT_EQ(d["seq"].get<uint64_t>(), model.seq());
}

TEST_F(ViewModelTest, EarthworksCarryTheirPointsAndAnAreaItsSoil) {
  cluster_.Start(kView, NodeRole::kObserver);
  cluster_.Run(500);
  ViewModel model(View(), Names());
  (void)model.Update(1, {}, {}, 1);
  auto ditch =
      A().Create(FeatureParams::Ditch({{40, 40, 2, 6}, {80, 40, 2, 6}, {90, 70, 1.5, 5}}, 1));
  auto flood = B().Create(FeatureParams::Area({{10, 80, 0, 0}, {40, 80, 0, 0}, {25, 110, 0, 0}},
                                              Material::kWater, 25.0));
  ASSERT_TRUE(ditch.ok()) << ditch.error().message;
  ASSERT_TRUE(flood.ok()) << flood.error().message;
  cluster_.Run(300);
  const nlohmann::json d = model.Update(2, {}, {}, 1);
  ASSERT_EQ(d["features"].size(), 2u);
  for (const auto& f : d["features"]) {
    if (f["id"] == ditch.value().ToString()) {
      EXPECT_EQ(f["type"], "ditch");
      ASSERT_EQ(f["points"].size(), 3u);
      EXPECT_EQ(f["points"][2], nlohmann::json({90.0, 70.0, 1.5, 5.0}));
      EXPECT_FALSE(f.contains("soil"));
    } else {
      EXPECT_EQ(f["type"], "area");
      EXPECT_EQ(f["soil"], "water");
      EXPECT_DOUBLE_EQ(f["level"].get<double>(), 25.0);
      EXPECT_EQ(f["points"].size(), 3u);
    }
  }
  // A ditch's breach is shown as one, like a berm's.
  auto pieces = B().Breach(ditch.value(), 10, 5);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  cluster_.Run(300);
  const nlohmann::json b = model.Update(3, {}, {}, 1);
  size_t breaches = 0;
  for (const auto& e : b["events"]) breaches += e["kind"] == "breach" ? 1 : 0;
  EXPECT_EQ(breaches, pieces.value().size());
}

TEST_F(ViewModelTest, ProcessesGoingSilentAndComingBackAreEvents) {
  cluster_.Start(kView, NodeRole::kObserver);
  ViewModel model(View(), Names());
  ProcessRow row;
  row.name = "node-a";
  row.reachable = true;
  row.signed_on = true;
  row.silent = false;
  auto kinds = [](const nlohmann::json& d) {
    std::vector<std::string> k;
    for (const auto& e : d["events"]) k.push_back(e["kind"]);
    return k;
  };
  EXPECT_EQ(kinds(model.Update(1, {row}, {}, 1)), std::vector<std::string>{"joined"});
  row.silent = true;
  row.reachable = false;
  nlohmann::json d = model.Update(2, {row}, {}, 1);
  EXPECT_EQ(kinds(d), std::vector<std::string>{"silent"});
  ASSERT_EQ(d["processes"].size(), 1u);
  EXPECT_EQ(d["processes"][0]["silent"], true);
  row.silent = false;
  row.reachable = true;
  EXPECT_EQ(kinds(model.Update(3, {row}, {}, 1)), std::vector<std::string>{"back"});
  VehicleView v{"node-a/0", "node-a", "tank", 10, 20, 0.5, 3, true};
  d = model.Update(4, {row}, {v}, 1);
  ASSERT_EQ(d["vehicles"].size(), 1u);
  EXPECT_EQ(d["vehicles"][0],
            nlohmann::json::array({"node-a/0", "node-a", "tank", 10.0, 20.0, 0.5, 3.0, true, 0}));
  EXPECT_TRUE(model.Update(5, {row}, {v}, 1).is_null());
}

TEST_F(ViewModelTest, ADigestThatKeepsDifferingFromTheServersIsAnEventOnceAndSoIsItsReturn) {
  cluster_.Start(kView, NodeRole::kObserver);
  ViewModel model(View(), Names());
  ProcessRow server, node;
  server.name = "server";
  server.role = "server";
  node.name = "node-a";
  node.role = "node";
  for (ProcessRow* r : {&server, &node}) {
    r->reachable = true;
    r->silent = false;
    r->digest = "aaaa";
  }
  auto kinds = [](const nlohmann::json& d) {
    std::vector<std::string> k;
    if (d.is_null() || !d.contains("events")) return k;
    for (const auto& e : d["events"]) k.push_back(e["kind"]);
    return k;
  };
  const int64_t t0 = 1000, wait = ViewModel::kDiffersAfterMs;
  EXPECT_EQ(kinds(model.Update(t0, {server, node}, {}, 1)),
            (std::vector<std::string>{"joined", "joined"}));
  // A change on its way: the node's digest differs for less than the wait, then agrees.
  node.digest = "bbbb";
  EXPECT_EQ(kinds(model.Update(t0 + 10, {server, node}, {}, 1)), std::vector<std::string>{});
  node.digest = "aaaa";
  EXPECT_EQ(kinds(model.Update(t0 + wait - 10, {server, node}, {}, 1)), std::vector<std::string>{});
  // A lasting difference the node does not know of (its own flag stays down): one event.
  node.digest = "cccc";
  EXPECT_EQ(kinds(model.Update(t0 + wait, {server, node}, {}, 1)), std::vector<std::string>{});
  EXPECT_EQ(kinds(model.Update(t0 + 2 * wait - 1, {server, node}, {}, 1)),
            std::vector<std::string>{});
  EXPECT_EQ(kinds(model.Update(t0 + 2 * wait, {server, node}, {}, 1)),
            std::vector<std::string>{"differs"});
  node.counters["received"] = 1;  // the row changes, the difference goes on: no new event
  EXPECT_EQ(kinds(model.Update(t0 + 3 * wait, {server, node}, {}, 1)), std::vector<std::string>{});
  // Unreachable, it has no digest to compare; back and agreeing, the log says so.
  node.reachable = false;
  EXPECT_EQ(kinds(model.Update(t0 + 4 * wait, {server, node}, {}, 1)), std::vector<std::string>{});
  node.reachable = true;
  node.digest = "aaaa";
  EXPECT_EQ(kinds(model.Update(t0 + 5 * wait, {server, node}, {}, 1)),
            std::vector<std::string>{"matches"});
  const nlohmann::json snap = model.Snapshot(t0 + 5 * wait);
  std::vector<std::string> logged;
  for (const auto& e : snap["events"]) logged.push_back(e["kind"]);
  EXPECT_EQ(logged, (std::vector<std::string>{"joined", "joined", "differs", "matches"}));
}

TEST_F(ViewModelTest, AVehicleDeltaCarriesTheVehiclesThatChangedAndTheIdsGone) {
  cluster_.Start(kView, NodeRole::kObserver);
  ViewModel model(View(), Names());
  VehicleView a{"node-a/0", "node-a", "tank", 10, 20, 0.5, 3, true};
  VehicleView b{"node-b/0", "node-b", "jeep", 50, 60, 1.0, 5, true};
  nlohmann::json d = model.Update(1, {}, {a, b}, 1);
  ASSERT_EQ(d["vehicles"].size(), 2u);
  b.x_m += 1.0;
  d = model.Update(2, {}, {a, b}, 1);
  ASSERT_EQ(d["vehicles"].size(), 1u);
  EXPECT_EQ(d["vehicles"][0][0], "node-b/0");
  EXPECT_DOUBLE_EQ(d["vehicles"][0][3].get<double>(), 51.0);
  EXPECT_FALSE(d.contains("vehicles_removed"));
  // Nothing changed: no delta; then a is no longer listed, b is dead.
  EXPECT_TRUE(model.Update(3, {}, {a, b}, 1).is_null());
  b.alive = false;
  d = model.Update(4, {}, {b}, 1);
  ASSERT_EQ(d["vehicles_removed"], nlohmann::json::array({"node-a/0"}));
  ASSERT_EQ(d["vehicles"].size(), 1u);
  EXPECT_EQ(d["vehicles"][0][7], false);
  const nlohmann::json s = model.Snapshot(5);
  ASSERT_EQ(s["vehicles"].size(), 1u);
  EXPECT_EQ(s["vehicles"][0][0], "node-b/0");
  // A vehicle gone while no delta was sent is still reported gone.
  EXPECT_TRUE(model.Update(6, {}, {b}, 1).is_null());
  d = model.Update(7, {}, {}, 1);
  EXPECT_EQ(d["vehicles_removed"], nlohmann::json::array({"node-b/0"}));
  EXPECT_EQ(model.Snapshot(8)["vehicles"].size(), 0u);
}

// With a frame asked for, a vehicle the page knows that only moved goes out in the binary
// message under the tick's seq, its slot the one its row named; new vehicles keep their JSON row;
// a gone vehicle's slot is given to the next new one.
TEST_F(ViewModelTest, MovesOfKnownVehiclesGoToTheBinaryFrameUnderTheirSlots) {
  cluster_.Start(kView, NodeRole::kObserver);
  ViewModel model(View(), Names());
  VehicleView a{"node-a/0", "node-a", "tank", 10, 20, 0.5, 3, true};
  VehicleView b{"node-b/0", "node-b", "jeep", 50, 60, 1.0, 5, true};
  std::string frame = "stale";
  nlohmann::json d = model.Update(1, {}, {a, b}, 1, &frame);
  EXPECT_TRUE(frame.empty());
  ASSERT_EQ(d["vehicles"].size(), 2u);
  const uint32_t slot_b = d["vehicles"][1][8];
  EXPECT_NE(d["vehicles"][0][8], d["vehicles"][1][8]);
  b.x_m = 51.25;
  b.heading_rad = 1.0 + 2 * std::numbers::pi;  // sent as its angle in (-pi, pi]
  b.alive = false;
  d = model.Update(2, {}, {a, b}, 1, &frame);
  EXPECT_TRUE(d.is_null());  // the move alone: no JSON
  auto decoded = DecodeVehicleFrame(frame);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  EXPECT_EQ(decoded.value().seq, model.seq());
  EXPECT_EQ(decoded.value().t_ms, 2);
  ASSERT_EQ(decoded.value().records.size(), 1u);
  const VehicleRecord& r = decoded.value().records[0];
  EXPECT_EQ(r.slot, slot_b);
  EXPECT_DOUBLE_EQ(r.x_m, 51.25);
  EXPECT_DOUBLE_EQ(r.z_m, 60.0);
  EXPECT_NEAR(r.heading_rad, 1.0, 1e-4);
  EXPECT_DOUBLE_EQ(r.speed_mps, 5.0);
  EXPECT_FALSE(r.alive);
  // A changes owner (its row again), B is gone, C is new (a fresh slot: B's is freed after the
  // tick's new vehicles); the JSON and the empty frame share the seq.
  a.owner = "node-b";
  VehicleView c{"node-a/1", "node-a", "truck", 5, 5, 0, 0, true};
  d = model.Update(3, {}, {a, c}, 1, &frame);
  EXPECT_TRUE(frame.empty());
  ASSERT_EQ(d["vehicles"].size(), 2u);
  EXPECT_EQ(d["vehicles"][0][1], "node-b");
  EXPECT_EQ(d["vehicles"][1][0], "node-a/1");
  const uint32_t slot_c = d["vehicles"][1][8];
  EXPECT_NE(slot_c, slot_b);
  EXPECT_EQ(d["vehicles_removed"], nlohmann::json::array({"node-b/0"}));
  EXPECT_EQ(d["seq"], model.seq());
  // The next new vehicle takes B's slot.
  VehicleView e{"node-a/2", "node-a", "jeep", 7, 7, 0, 0, true};
  d = model.Update(4, {}, {a, c, e}, 1, &frame);
  ASSERT_EQ(d["vehicles"].size(), 1u);
  EXPECT_EQ(d["vehicles"][0][8], slot_b);
  // The snapshot names every vehicle's slot.
  const nlohmann::json s = model.Snapshot(5);
  ASSERT_EQ(s["vehicles"].size(), 3u);
  for (const auto& row : s["vehicles"]) {
    EXPECT_EQ(row[8], row[0] == "node-a/1" ? slot_c : row[0] == "node-a/2" ? slot_b : 0u);
  }
}

TEST(VehicleFrameTest, AFrameOfTheWrongSizeOrHeaderIsRefusedNamingIt) {
  std::string frame = VehicleFrameHeader(7, 1000, 2);
  AppendVehicleRecord(frame, 3, VehicleView{"x", "o", "tank", 1, 2, 0, 0, true});
  auto r = DecodeVehicleFrame(frame);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("2 records need 56 bytes, not 40"), std::string::npos)
      << r.error().message;
  frame[0] = 'X';
  EXPECT_FALSE(DecodeVehicleFrame(frame).ok());
}

TEST_F(ViewModelTest, ABridgeChangeResendsTheBridgesItRePlacesAndNothingElse) {
  cluster_.Start(kView, NodeRole::kObserver);
  cluster_.Run(500);
  ViewModel model(View(), Names());
  auto crater = A().Create(FeatureParams::Crater(20, 100, 3));
  ASSERT_TRUE(crater.ok());
  cluster_.Run(300);
  ASSERT_EQ(model.Update(1, {}, {}, 1)["features"].size(), 1u);
  // Two bridges over each other, made at once by A and B: both kept, the lower ID placed.
  auto one = A().Create(FeatureParams::Bridge(60, 60, 0.0, 4, 8, 16, 8, 2, 2));
  auto two = B().Create(FeatureParams::Bridge(64, 62, 0.0, 4, 8, 16, 8, 2, 2));
  ASSERT_TRUE(one.ok() && two.ok());
  cluster_.Run(300);
  nlohmann::json d = model.Update(2, {}, {}, 1);
  ASSERT_EQ(d["features"].size(), 2u);
  const bool one_lower = one.value() < two.value();
  const FeatureId lower = one_lower ? one.value() : two.value();
  const FeatureId upper = one_lower ? two.value() : one.value();
  for (const auto& f : d["features"]) EXPECT_EQ(f["placed"], f["id"] == lower.ToString());
  // The first one destroyed, the second is placed: it is resent, the crater is not.
  ASSERT_TRUE((one_lower ? A() : B()).Destroy(lower).ok());
  cluster_.Run(300);
  d = model.Update(3, {}, {}, 1);
  EXPECT_EQ(d["removed"], nlohmann::json::array({lower.ToString()}));
  ASSERT_EQ(d["features"].size(), 1u);
  EXPECT_EQ(d["features"][0]["id"], upper.ToString());
  EXPECT_EQ(d["features"][0]["placed"], true);
  EXPECT_EQ(model.feature_count(), 2u);
}

// A change that reached the view alone before its author crashed is dropped once the author's
// next incarnation holds less (docs/protocol.md "Observers"): the page removes the feature, and
// the slot, when the author fills it with its next change, is noted like any new change.
TEST_F(ViewModelTest, AChangeOnlyTheViewHeldLeavesThePageAndItsSlotIsNotedAgainWhenFilled) {
  cluster_.Start(kView, NodeRole::kObserver);
  ASSERT_TRUE(A().Create(FeatureParams::Crater(30, 30, 3)).ok());
  cluster_.Run(1000);
  ViewModel model(View(), Names());
  ASSERT_EQ(model.Update(1, {}, {}, 1)["features"].size(), 1u);
  cluster_.net().faults().Partition({kTestA, kView}, {kTestServer, kTestB});
  auto lost = A().Create(FeatureParams::Crater(90, 90, 3));
  ASSERT_TRUE(lost.ok());
  cluster_.Run(100);
  cluster_.Crash(kTestA);
  cluster_.net().faults().Heal();
  ASSERT_EQ(model.Update(2, {}, {}, 1)["features"].size(), 1u);
  ASSERT_EQ(model.feature_count(), 2u);
  Replica& a = cluster_.Start(kTestA, NodeRole::kNode);
  for (int i = 0; i < 1000 && View().anti_entropy().stats().slots_dropped == 0; ++i) {
    cluster_.Run(10);
  }
  ASSERT_EQ(View().anti_entropy().stats().slots_dropped, 1u);
  nlohmann::json d = model.Update(3, {}, {}, 1);
  EXPECT_EQ(d["removed"], nlohmann::json::array({lost.value().ToString()}));
  EXPECT_EQ(model.feature_count(), 1u);
  for (int i = 0; i < 1000 && !a.signed_on(); ++i) cluster_.Run(10);
  ASSERT_TRUE(a.signed_on());
  auto next = a.Create(FeatureParams::Crater(60, 20, 2));
  ASSERT_TRUE(next.ok());
  ASSERT_EQ(a.log(kTestA)->Find(2)->id, next.value());  // the slot the lost crater had
  cluster_.Run(300);
  d = model.Update(4, {}, {}, 1);
  ASSERT_EQ(d["features"].size(), 1u);
  EXPECT_EQ(d["features"][0]["id"], next.value().ToString());
  ASSERT_EQ(d["features"][0]["history"].size(), 1u);
  EXPECT_EQ(d["features"][0]["history"][0]["change_seq"], 2);
  EXPECT_EQ(model.feature_count(), 2u);
  EXPECT_EQ(View().Digest(), S().Digest());
}

// The page draws a bridge as the solids vehicles meet (vehicle/bridge_solids.h): the plan of
// each deck slab, pier and a destroyed span's rubble, corner for corner.
TEST(ViewModelBridge, ABridgeCarriesThePlanOfTheSolidsVehiclesMeet) {
  for (const bool destroyed : {false, true}) {
    Record r;
    r.params = FeatureParams::Bridge(100, 200, 0.3, 10, 30, 40, 20, 6, 5);
    if (destroyed) r.params.status = BridgeStatus::kDestroyed;
    const nlohmann::json j = FeatureJson({1, 1, 1}, r);
    const std::vector<Solid> plans = BridgeSolidPlans(r.params);
    ASSERT_EQ(j["solids"].size(), plans.size());
    ASSERT_EQ(plans.size(), 7u);  // 3 slabs, or 2 and the rubble; 4 piers
    size_t piers = 0, rubble = 0;
    for (size_t k = 0; k < plans.size(); ++k) {
      const Solid& s = plans[k];
      const auto& out = j["solids"][k];
      piers += out["kind"] == "pier";
      rubble += out["kind"] == "rubble";
      EXPECT_EQ(out["kind"], s.deck ? "deck" : s.rubble ? "rubble" : "pier");
      // The first corner is (a0, r0) in the bridge's frame.
      double a = 0, right = 0;
      s.ToLocal(out["corners"][0][0].get<double>(), out["corners"][0][1].get<double>(), a, right);
      EXPECT_NEAR(a, s.a0_m, 1e-9);
      EXPECT_NEAR(right, s.r0_m, 1e-9);
      s.ToLocal(out["corners"][2][0].get<double>(), out["corners"][2][1].get<double>(), a, right);
      EXPECT_NEAR(a, s.a1_m, 1e-9);
      EXPECT_NEAR(right, s.r1_m, 1e-9);
    }
    EXPECT_EQ(piers, 4u);
    EXPECT_EQ(rubble, destroyed ? 1u : 0u);
  }
}

}  // namespace
}  // namespace dt
