// Tests the rules for what a replica believes from the wire (docs/protocol.md, "Rules for what is
// believed"): membership from the exercise file, role claims, claims about a node's counters, and
// Lamport clocks too far ahead. Each hostile PDU is sent by a bus of its own on the same network.
#include <cstdint>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kStandby = testing::kTestStandby;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;
const NodeAddress kC{1, 3};  // a member node with no replica: its PDUs are forged by the tests
const NodeAddress kStranger{77, 77};

ReplicaConfig Defaults() {
  ReplicaConfig c = testing::TestReplicaConfig();
  c.members = {{kServer, NodeRole::kServer},
               {kStandby, NodeRole::kStandby},
               {kA, NodeRole::kNode},
               {kB, NodeRole::kNode},
               {kC, NodeRole::kNode}};
  return c;
}

class RulesTest : public ::testing::Test, public testing::ServerAndTwoNodes {
 protected:
  RulesTest() : ServerAndTwoNodes(3, Defaults()) {}

  static dtpdu::construct_t Crater(NodeAddress author, uint32_t number, uint32_t seq,
                                   uint64_t lamport) {
    FeaturePdu f;
    f.id = {author.site, author.host, number};
    f.params = FeatureParams::Crater(60, 60, 4);
    f.change.changed_by = author;
    f.change.change_seq = seq;
    f.change.lamport = lamport;
    return ToConstruct(f);
  }
  static dtpdu::max_feature_t Claim(NodeAddress subject, NodeRole role, int64_t seq,
                                    int64_t lamport) {
    dtpdu::max_feature_t m{};
    m.subject = ToPdu(subject);
    m.max_feature_number = seq;
    m.max_change_seq = seq;
    m.lamport = lamport;
    m.role = static_cast<uint8_t>(role);
    testing::StampTestGround(m);
    return m;
  }
  void ExpectAllEqualAndCaughtUp() {
    for (Replica* r : {&A(), &B(), &S()}) {
      EXPECT_TRUE(r->caught_up()) << r->config().address.ToString();
      EXPECT_EQ(r->Digest(), S().Digest()) << r->config().address.ToString();
    }
  }

  // On cluster_'s network, so declared after it (destroyed first).
};

TEST_F(RulesTest, AConstructFromANodeInNoExerciseFileIsRefusedEverywhere) {
  ASSERT_TRUE(BusAs(kStranger).Publish(Crater(kStranger, 1, 1, 5)).ok());
  cluster_.Run(500);
  for (Replica* r : {&A(), &B(), &S()}) {
    EXPECT_EQ(r->live_feature_count(), 0u);
    EXPECT_GE(r->counters().refused_stranger, 1u);
    EXPECT_EQ(r->log(kStranger), nullptr);
  }
  ExpectAllEqualAndCaughtUp();
}

TEST_F(RulesTest, AStrangersChangeFarAheadStallsNoOneAndARestartedNodeIsReady) {
  ASSERT_TRUE(BusAs(kStranger).Publish(Crater(kStranger, 1, 1000, 5)).ok());
  cluster_.Run(1000);
  ExpectAllEqualAndCaughtUp();
  cluster_.Crash(kB);
  cluster_.Run(300);
  Replica& b = cluster_.Start(kB, NodeRole::kNode);
  cluster_.Run(2000);
  EXPECT_TRUE(b.signed_on());
  EXPECT_TRUE(b.caught_up());
  EXPECT_EQ(b.Digest(), S().Digest());
}

// A member's change whose predecessors no live replica holds (its author gone for good, e.g. a
// node that crashed right after sending and never came back) is waited for gap_give_up_ms, then
// the gap is voided by the slot's authority (here the server), once: no permanent stall, and a
// node started afterwards signs on and is caught up with the same terrain.
TEST_F(RulesTest, AGapNoLiveReplicaCanFillIsGivenUpOnOnceAndNoOneStalls) {
  ASSERT_TRUE(BusAs(kC).Publish(Crater(kC, 3, 3, 5)).ok());
  cluster_.Run(5000);
  // Still waiting: a crashed author comes back within this time and voids its own gaps.
  for (Replica* r : {&A(), &B(), &S()}) {
    EXPECT_FALSE(r->caught_up()) << r->config().address.ToString();
    EXPECT_EQ(r->counters().gave_up, 0u);
  }
  cluster_.Run(Defaults().gap_give_up_ms);
  ExpectAllEqualAndCaughtUp();
  EXPECT_EQ(S().counters().gave_up, 2u);  // changes 1 and 2 of 1:3
  EXPECT_EQ(A().counters().gave_up + B().counters().gave_up, 0u);
  for (Replica* r : {&A(), &B(), &S()}) {
    EXPECT_EQ(r->live_feature_count(), 1u);  // the change that did arrive stands
    ASSERT_NE(r->log(kC), nullptr);
    EXPECT_EQ(r->log(kC)->contiguous(), 3);
  }
  cluster_.Crash(kB);
  cluster_.Run(300);
  Replica& b = cluster_.Start(kB, NodeRole::kNode);
  cluster_.Run(3000);
  EXPECT_TRUE(b.signed_on());
  EXPECT_TRUE(b.caught_up());
  EXPECT_EQ(b.Digest(), S().Digest());
  EXPECT_EQ(b.counters().gave_up, 0u);
}

TEST_F(RulesTest, AStrangerClaimingToBeTheServerMovesNoCounters) {
  const int64_t seq = A().own_change_seq();
  PduBus& forger = BusAs({90, 90});
  ASSERT_TRUE(forger.Publish(Claim(kA, NodeRole::kServer, 1000000, 5)).ok());
  cluster_.Run(500);
  EXPECT_EQ(A().own_change_seq(), seq);
  EXPECT_EQ(B().log(kA) == nullptr ? 0 : B().log(kA)->max_known(), 0);
  EXPECT_GE(A().counters().refused_stranger, 1u);
  auto id = A().Create(FeatureParams::Crater(30, 30, 2));
  ASSERT_TRUE(id.ok());
  cluster_.Run(500);
  ExpectAllEqualAndCaughtUp();
}

TEST_F(RulesTest, AMemberClaimingARoleItDoesNotHaveIsRefused) {
  ASSERT_TRUE(BusAs(kC).Publish(Claim(kA, NodeRole::kServer, 1000000, 5)).ok());
  cluster_.Run(300);
  EXPECT_GE(A().counters().refused_role, 1u);
  EXPECT_EQ(A().own_change_seq(), 0);
  EXPECT_EQ(B().log(kA) == nullptr ? 0 : B().log(kA)->max_known(), 0);
  ExpectAllEqualAndCaughtUp();
}

// Anti-entropy trusts no more than live traffic: a summary claiming the server's role (which would
// make its copies win the repair rule) or from a stranger is not heard, so a wrong prefix hash in
// it opens no difference.
TEST_F(RulesTest, AnAntiEntropySummaryWithAFalseRoleOrFromAStrangerIsNotHeard) {
  ASSERT_TRUE(A().Create(FeatureParams::Crater(30, 30, 2)).ok());
  cluster_.Run(500);
  const auto summary = [](NodeRole role) {
    dtpdu::anti_entropy_t p{};
    p.kind = static_cast<uint8_t>(AntiEntropyKind::kSummary);
    p.role = static_cast<uint8_t>(role);
    p.num_entries = 1;
    p.entries.resize(1);
    p.entries[0].author = ToPdu(kA);
    p.entries[0].seq = 1;
    p.entries[0].prefix_hash = 12345;  // not the hash of A's change 1
    p.entries[0].max_held = 1;
    return p;
  };
  const uint64_t role_refusals = A().counters().refused_role;
  const uint64_t stranger_refusals = A().counters().refused_stranger;
  ASSERT_TRUE(BusAs(kC).Publish(summary(NodeRole::kServer)).ok());
  ASSERT_TRUE(BusAs(kStranger).Publish(summary(NodeRole::kNode)).ok());
  cluster_.Run(300);
  EXPECT_GT(A().counters().refused_role, role_refusals);
  EXPECT_GT(A().counters().refused_stranger, stranger_refusals);
  EXPECT_FALSE(A().diverged());
  EXPECT_FALSE(B().diverged());
  ExpectAllEqualAndCaughtUp();
}

TEST_F(RulesTest, ANodesClaimAboutAnotherNodeIsNotEvidenceForAnyone) {
  ASSERT_TRUE(BusAs(kC).Publish(Claim(kA, NodeRole::kNode, 1000000, 5)).ok());
  cluster_.Run(300);
  EXPECT_EQ(A().own_change_seq(), 0);
  EXPECT_EQ(B().log(kA) == nullptr ? 0 : B().log(kA)->max_known(), 0);
  ExpectAllEqualAndCaughtUp();
}

TEST_F(RulesTest, TheStandbysClaimBeyondWhatASignedOnNodeMadeIsRefused) {
  ASSERT_TRUE(A().Create(FeatureParams::Crater(30, 30, 2)).ok());
  cluster_.Run(300);
  ASSERT_TRUE(BusAs(kStandby).Publish(Claim(kA, NodeRole::kStandby, 1000000, 5)).ok());
  cluster_.Run(300);
  EXPECT_GE(A().counters().refused_claim, 1u);
  EXPECT_EQ(A().own_change_seq(), 1);
  auto id = A().Create(FeatureParams::Crater(60, 30, 2));
  ASSERT_TRUE(id.ok());
  cluster_.Run(500);
  EXPECT_EQ(A().own_change_seq(), 2);
}

TEST_F(RulesTest, ALamportClockFarAheadIsRefusedAndLaterChangesStillTravel) {
  ASSERT_TRUE(
      BusAs(kC).Publish(Claim(kC, NodeRole::kNode, 0, std::numeric_limits<int64_t>::max())).ok());
  cluster_.Run(300);
  EXPECT_GE(A().counters().refused_lamport, 1u);
  auto id = A().Create(FeatureParams::Crater(30, 30, 2));
  ASSERT_TRUE(id.ok()) << id.error().message;
  cluster_.Run(500);
  EXPECT_NE(B().terrain().Find(id.value()), nullptr);
  ExpectAllEqualAndCaughtUp();
}

TEST_F(RulesTest, AChangeWithAClockFarAheadIsRefused) {
  PduBus& c = BusAs(kC);
  ASSERT_TRUE(c.Publish(Crater(kC, 1, 1, kMaxLamportLead + 1000)).ok());
  cluster_.Run(300);
  EXPECT_EQ(B().live_feature_count(), 0u);
  EXPECT_GE(B().counters().refused_lamport, 1u);
  // Within the lead it is an ordinary change.
  ASSERT_TRUE(c.Publish(Crater(kC, 1, 1, 1000)).ok());
  cluster_.Run(300);
  EXPECT_EQ(B().live_feature_count(), 1u);
}

TEST(RulesConfigTest, AReplicaMissingFromItsOwnMemberListIsAConfigError) {
  SimNetwork net(1, {});
  auto t = net.Join(kA, 1);
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = kA;
  bc.terrain_size_x_m = bc.terrain_size_z_m = 128.0;
  PduBus bus(*t, bc);
  ReplicaConfig rc = Defaults();
  rc.address = {1, 9};
  EXPECT_THROW(Replica(rc, HeightGrid(33, 4.0, 10.0f), bus), std::invalid_argument);
  rc.address = kA;
  rc.role = NodeRole::kServer;  // the file says node
  MemoryChangeStore store;
  rc.store = &store;
  EXPECT_THROW(Replica(rc, HeightGrid(33, 4.0, 10.0f), bus), std::invalid_argument);
}

}  // namespace
}  // namespace dt
