// Tests ground identity (docs/pdu.md "Ground identity"): every MaxFeature names the sender's
// ground; a member on another ground than the exercise's (the server's) is refused by the others
// and refuses itself, naming both digests; and a base ground's features (a saved terrain the
// exercise starts on) are every member's from the start.
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"
#include "terrain/base_ground.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kStandby = testing::kTestStandby;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;
const NodeAddress kC{1, 3};     // a member node with no replica: its PDUs are forged
const NodeAddress kView{1, 0};  // an observer

ReplicaConfig Defaults() {
  ReplicaConfig c = testing::TestReplicaConfig();
  c.members = {{kServer, NodeRole::kServer}, {kStandby, NodeRole::kStandby},
               {kA, NodeRole::kNode},        {kB, NodeRole::kNode},
               {kC, NodeRole::kNode},        {kView, NodeRole::kObserver}};
  c.ground_source = "the test ground";
  return c;
}

// The test ground with one post raised by 1 cm: another ground of the same size.
BaseGround OtherGround() {
  HeightGrid g = testing::TestGround();
  g.set_post(16, 16, g.post(16, 16) + 0.01f);
  return BaseGround{std::move(g), {}};
}

class GroundTest : public ::testing::Test {
 protected:
  GroundTest() : cluster_(11, testing::TestGround(), Defaults()) {
    cluster_.Start(kServer, NodeRole::kServer, &store_);
    cluster_.Start(kA, NodeRole::kNode);
    cluster_.Run(1000);
  }
  Replica& S() { return cluster_.at(kServer); }
  Replica& A() { return cluster_.at(kA); }

  MemoryChangeStore store_;
  SimCluster cluster_;
};

TEST_F(GroundTest, EveryMemberNamesItsGroundAndTheSameGroundIsAccepted) {
  const TerrainDigest test_ground = ComputeDigest(testing::TestGround());
  EXPECT_EQ(S().ground_digest(), test_ground);
  EXPECT_EQ(A().ground_digest(), test_ground);
  EXPECT_TRUE(A().signed_on());
  EXPECT_FALSE(A().ground_refused());
  EXPECT_TRUE(S().ground_mismatches().empty());
  EXPECT_EQ(S().counters().refused_ground, 0u);
  EXPECT_EQ(A().counters().refused_ground, 0u);
}

// A digest the caller already holds (ReplicaConfig::ground_digest) is the one the replica names
// and judges by; it is not computed again. Given a digest of another ground, the replica believes
// it: the caller must pass exactly its ground's.
TEST(GroundDigestGivenTest, TheGivenDigestIsNamedAndJudgedBy) {
  const TerrainDigest test_ground = ComputeDigest(testing::TestGround());
  ReplicaConfig given = Defaults();
  given.ground_digest = test_ground;
  MemoryChangeStore store;
  SimCluster cluster(12, testing::TestGround(), given);
  cluster.Start(kServer, NodeRole::kServer, &store);
  cluster.Start(kA, NodeRole::kNode);
  cluster.Run(1000);
  EXPECT_EQ(cluster.at(kServer).ground_digest(), test_ground);
  EXPECT_EQ(cluster.at(kA).ground_digest(), test_ground);
  EXPECT_TRUE(cluster.at(kA).signed_on());
  EXPECT_TRUE(cluster.at(kServer).ground_mismatches().empty());

  ReplicaConfig wrong = Defaults();
  wrong.ground_digest = ComputeDigest(OtherGround());
  SimCluster other(13, testing::TestGround(), wrong);
  EXPECT_EQ(other.Start(kA, NodeRole::kNode).ground_digest(), *wrong.ground_digest);
}

TEST_F(GroundTest, ANodeOnAnotherGroundRefusesItselfAndIsRefusedByTheOthers) {
  const BaseGround other = OtherGround();
  const TerrainDigest other_digest = ComputeDigest(other);
  ASSERT_NE(other_digest, S().ground_digest());
  ASSERT_TRUE(A().Create(FeatureParams::Crater(40, 40, 3)).ok());
  Replica& b = cluster_.Start(kB, NodeRole::kNode, nullptr, nullptr, &other);
  cluster_.Run(3000);

  // B refuses itself: it names the exercise's ground and who reported it, never signs on, takes
  // no change and issues none.
  EXPECT_TRUE(b.ground_refused());
  ASSERT_TRUE(b.exercise_ground_digest().has_value());
  EXPECT_EQ(*b.exercise_ground_digest(), S().ground_digest());
  EXPECT_EQ(b.exercise_ground_reporter(), kServer);
  EXPECT_FALSE(b.signed_on());
  EXPECT_EQ(b.live_feature_count(), 0u);
  EXPECT_GT(b.counters().refused_ground, 0u);
  auto refused = b.Create(FeatureParams::Crater(60, 60, 3));
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find(other_digest.ToHex()), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find(S().ground_digest().ToHex()), std::string::npos)
      << refused.error().message;

  // The others refuse it and name its ground; they go on as before.
  for (Replica* r : {&S(), &A()}) {
    EXPECT_GT(r->counters().refused_ground, 0u) << r->config().address.ToString();
    const auto mismatches = r->ground_mismatches();
    ASSERT_EQ(mismatches.size(), 1u) << r->config().address.ToString();
    EXPECT_EQ(mismatches.begin()->first, kB);
    EXPECT_EQ(mismatches.begin()->second, other_digest);
    EXPECT_FALSE(r->ground_refused());
    EXPECT_TRUE(r->caught_up()) << r->config().address.ToString();
  }
  EXPECT_EQ(A().Digest(), S().Digest());
  ASSERT_TRUE(A().Create(FeatureParams::Crater(80, 80, 3)).ok());
  cluster_.Run(500);
  EXPECT_EQ(S().live_feature_count(), 2u);
  EXPECT_EQ(b.live_feature_count(), 0u);
}

TEST_F(GroundTest, APduFromAMemberThatReportedAnotherGroundIsRefused) {
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = kC;
  bc.terrain_size_x_m = bc.terrain_size_z_m = 128.0;
  bc.clock = [] { return 0u; };
  auto transport = cluster_.net().Join(kC, 1);
  PduBus c(*transport, bc);
  dtpdu::max_feature_t report{};
  report.subject = ToPdu(kC);
  report.lamport = 1;
  report.role = static_cast<uint8_t>(NodeRole::kNode);
  report.ground_digest[0] = 1;  // not the test ground
  report.ground_digest[1] = 2;
  ASSERT_TRUE(c.Publish(report).ok());
  cluster_.Run(100);
  FeaturePdu f;
  f.id = {kC.site, kC.host, 1};
  f.params = FeatureParams::Crater(60, 60, 4);
  f.change.changed_by = kC;
  f.change.change_seq = 1;
  f.change.lamport = 2;
  ASSERT_TRUE(c.Publish(ToConstruct(f)).ok());
  cluster_.Run(500);
  for (Replica* r : {&S(), &A()}) {
    EXPECT_EQ(r->live_feature_count(), 0u) << r->config().address.ToString();
    EXPECT_EQ(r->log(kC), nullptr) << r->config().address.ToString();
    EXPECT_GE(r->counters().refused_ground, 2u) << r->config().address.ToString();
    EXPECT_EQ(r->ground_mismatches().at(kC), (TerrainDigest{1, 2}));
    // A node's other ground is the node's problem: no one refuses itself for it.
    EXPECT_FALSE(r->ground_refused());
  }
  // Restarted on the exercise's ground, its next MaxFeature names that ground, and it is believed
  // again: the earlier report does not refuse the one that corrects it.
  const TerrainDigest test_ground = ComputeDigest(testing::TestGround());
  report.ground_digest[0] = static_cast<int64_t>(test_ground.high);
  report.ground_digest[1] = static_cast<int64_t>(test_ground.low);
  report.lamport = 3;
  ASSERT_TRUE(c.Publish(report).ok());
  cluster_.Run(100);
  f.change.lamport = 4;
  ASSERT_TRUE(c.Publish(ToConstruct(f)).ok());
  cluster_.Run(500);
  for (Replica* r : {&S(), &A()}) {
    EXPECT_TRUE(r->ground_mismatches().empty()) << r->config().address.ToString();
    EXPECT_EQ(r->live_feature_count(), 1u) << r->config().address.ToString();
  }
}

TEST_F(GroundTest, AStandbyAndAnObserverOnAnotherGroundRefuseThemselves) {
  const BaseGround other = OtherGround();
  MemoryChangeStore standby_store;
  Replica& standby = cluster_.Start(kStandby, NodeRole::kStandby, &standby_store, nullptr, &other);
  Replica& view = cluster_.Start(kView, NodeRole::kObserver, nullptr, nullptr, &other);
  cluster_.Run(1000);  // a report of the server's reaches them
  ASSERT_TRUE(A().Create(FeatureParams::Crater(40, 40, 3)).ok());
  cluster_.Run(2000);
  for (Replica* r : {&standby, &view}) {
    EXPECT_TRUE(r->ground_refused()) << r->config().address.ToString();
    EXPECT_EQ(r->exercise_ground_digest(), S().ground_digest());
    EXPECT_FALSE(r->signed_on()) << r->config().address.ToString();
    EXPECT_EQ(r->live_feature_count(), 0u) << r->config().address.ToString();
  }
  EXPECT_EQ(S().ground_mismatches().count(kStandby), 1u);
  // The server is its own authority on its ground: a standby's other ground never refuses it.
  EXPECT_FALSE(S().ground_refused());
  EXPECT_FALSE(A().ground_refused());
  EXPECT_TRUE(A().caught_up());
}

TEST(BaseGroundReplica, TheBaseGroundsFeaturesAreEveryMembersAndNoOnesToChange) {
  // A saved terrain with a crater and a bridge, as base ground.
  Terrain saved(testing::TestGround());
  ASSERT_TRUE(saved.Add({1, 1, 7}, FeatureParams::Crater(30, 30, 4)).ok());
  ASSERT_TRUE(saved.Add({1, 2, 3}, FeatureParams::Crater(90, 90, 5)).ok());
  const BaseGround base = BaseGroundFromTerrain(saved);
  ASSERT_EQ(base.features.size(), 2u);
  EXPECT_EQ(base.features[0].first, (FeatureId{0, 0, 1}));  // 1:1:7 sorts first
  EXPECT_EQ(base.features[1].first, (FeatureId{0, 0, 2}));

  SimCluster cluster(5, testing::TestGround(), Defaults());
  MemoryChangeStore store;
  // SimCluster's own ground is bare; every member here starts on the base ground.
  Replica& s = cluster.Start(kServer, NodeRole::kServer, &store, nullptr, &base);
  Replica& a = cluster.Start(kA, NodeRole::kNode, nullptr, nullptr, &base);
  cluster.Run(1500);
  ASSERT_TRUE(a.signed_on());
  EXPECT_EQ(a.ground_digest(), ComputeDigest(base));
  EXPECT_NE(a.ground_digest(), ComputeDigest(testing::TestGround()));
  EXPECT_EQ(a.terrain().feature_count(), 2u);
  EXPECT_EQ(a.live_feature_count(), 0u);  // no records: nobody issued them
  EXPECT_FALSE(a.Destroy({0, 0, 1}).ok());
  EXPECT_FALSE(a.Modify({0, 0, 2}, FeatureParams::Crater(90, 90, 6)).ok());
  // A issues its own numbers, which collide with nothing of the ground.
  auto made = a.Create(FeatureParams::Crater(60, 60, 3));
  ASSERT_TRUE(made.ok());
  EXPECT_EQ(OriginOf(made.value()), kA);
  cluster.Run(500);
  EXPECT_EQ(s.terrain().feature_count(), 3u);
  EXPECT_EQ(s.Digest(), a.Digest());
  EXPECT_TRUE(s.caught_up());
}

}  // namespace
}  // namespace dt
