// Regression tests for the recovery promises: no feature ID issued twice across restarts (a
// reservation survives the crash), and no acknowledged change voided while the server that
// acknowledged it is silent (issue: a blocked DDS writer made the server look silent).
#include <set>

#include <gtest/gtest.h>

#include "engine/id_reservation.h"
#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;

ReplicaConfig Defaults() { return testing::TestReplicaConfig(); }

// The reservation outlives the replicas, as A's file would (a base, so built before them).
struct IdsOfA {
  MemoryIdReservation ids_a_;
};

class RecoveryTest : public ::testing::Test, protected IdsOfA, public testing::ServerAndTwoNodes {
 protected:
  RecoveryTest() : ServerAndTwoNodes(7, Defaults(), &ids_a_) {}
};

// Reproduces issue 15 item 2: while the server and B are down, A creates two features; A is then
// killed and restarted without its state. Everyone it could learn from knows only the earlier
// acknowledged maximum, so counting the skip from there gave the same two numbers again.
TEST_F(RecoveryTest, ANodeRestartedAfterCreatingAloneNeverReissuesAnId) {
  ASSERT_TRUE(A().signed_on());
  ASSERT_TRUE(A().Create(FeatureParams::Crater(20, 20, 2)).ok());
  cluster_.Run(600);
  ASSERT_EQ(A().acknowledged_change_seq(), 1);
  // A restarted incarnation: it learned the acknowledged maximum when it signed on, as the next
  // one will.
  cluster_.Crash(kA);
  cluster_.Run(300);
  cluster_.Start(kA, NodeRole::kNode, nullptr, &ids_a_);
  cluster_.Run(1500);
  ASSERT_TRUE(A().signed_on());
  cluster_.Crash(kServer);
  cluster_.Crash(kB);
  std::set<uint32_t> alone;
  for (int i = 0; i < 2; ++i) {
    auto id = A().Create(FeatureParams::Crater(40 + 20 * i, 40, 2));
    ASSERT_TRUE(id.ok()) << id.error().message;
    alone.insert(id.value().number);
  }
  cluster_.Run(100);
  cluster_.Crash(kA);
  cluster_.Run(300);
  cluster_.Start(kServer, NodeRole::kServer, &store_);
  cluster_.Start(kB, NodeRole::kNode);
  Replica& a = cluster_.Start(kA, NodeRole::kNode, nullptr, &ids_a_);
  cluster_.Run(3000);
  ASSERT_TRUE(a.signed_on());
  for (int i = 0; i < 3; ++i) {
    auto id = a.Create(FeatureParams::Crater(30 + 30 * i, 90, 2));
    ASSERT_TRUE(id.ok()) << id.error().message;
    EXPECT_EQ(alone.count(id.value().number), 0u)
        << "feature number " << id.value().number << " was issued twice";
    EXPECT_GT(id.value().number, *alone.rbegin());
  }
}

TEST_F(RecoveryTest, NumbersAreReservedAWindowAtATime) {
  const uint64_t before = ids_a_.writes();
  for (int i = 0; i < 10; ++i)
    ASSERT_TRUE(A().Create(FeatureParams::Crater(10 + 8 * i, 20, 2)).ok());
  // One write covers a window (64 here) of creates.
  EXPECT_EQ(ids_a_.writes(), before + 1);
  ASSERT_TRUE(ids_a_.reserved().has_value());
  EXPECT_GE(*ids_a_.reserved(), A().own_feature_number());
}

TEST_F(RecoveryTest, ACreateWhoseNumberCannotBeReservedIsRefusedAndChangesNothing) {
  // Use up the current reservation so the next create needs a write.
  while (!ids_a_.reserved() || A().own_feature_number() < *ids_a_.reserved()) {
    const double x = 4.0 + static_cast<double>(A().own_feature_number() % 30) * 4.0;
    ASSERT_TRUE(A().Create(FeatureParams::Crater(x, 60, 1)).ok());
    cluster_.Run(50);
  }
  ids_a_.set_fail(true);
  const int64_t number = A().own_feature_number();
  const int64_t seq = A().own_change_seq();
  const std::string digest = A().Digest();
  auto id = A().Create(FeatureParams::Crater(100, 100, 2));
  ASSERT_FALSE(id.ok());
  EXPECT_NE(id.error().message.find("reserve"), std::string::npos) << id.error().message;
  EXPECT_EQ(A().own_feature_number(), number);
  EXPECT_EQ(A().own_change_seq(), seq);
  EXPECT_EQ(A().Digest(), digest);
  ids_a_.set_fail(false);
  EXPECT_TRUE(A().Create(FeatureParams::Crater(100, 100, 2)).ok());
}

// Reproduces issue 15 item 1 in the engine: A's changes are acknowledged; A restarts without
// state and learns from the server that they are durable; then the server falls silent (its
// writes blocked) before A has fetched them. The only other candidate, B, restarted empty. The
// void rule used to forget the silent server's claim and void acknowledged changes (B, restarted
// empty, answered every request with nothing).
TEST(RecoverySilentServerTest, AcknowledgedChangesAreNeverVoidedWhileTheServerIsSilent) {
  MemoryChangeStore store;
  SimCluster cluster(11, HeightGrid(33, 4.0, 10.0f), Defaults());
  cluster.Start(kServer, NodeRole::kServer, &store);
  cluster.Start(kA, NodeRole::kNode);
  cluster.Start(kB, NodeRole::kNode);
  cluster.Run(1000);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(cluster.at(kA).Create(FeatureParams::Crater(20 + 15 * i, 30, 2)).ok());
  }
  cluster.Run(600);
  ASSERT_EQ(cluster.at(kA).acknowledged_change_seq(), 5);
  cluster.Crash(kA);
  cluster.Crash(kB);
  cluster.Run(300);
  Replica& a = cluster.Start(kA, NodeRole::kNode);
  for (int t = 0; t < 3000 && a.acknowledged_change_seq() < 5; t += 10) cluster.Run(10);
  ASSERT_EQ(a.acknowledged_change_seq(), 5);
  ASSERT_EQ(a.live_feature_count(), 0u);
  // From here on nothing the server sends arrives. B restarts empty: a candidate that holds
  // nothing, as the other restarted nodes were in the campaign.
  cluster.net().faults().Partition({kServer}, {kA, kB});
  cluster.Start(kB, NodeRole::kNode);
  cluster.Run(6000);
  EXPECT_TRUE(a.signed_on());
  EXPECT_EQ(a.counters().voided, 0u);
  // It knows it is missing acknowledged changes: it once reported caught up here, having
  // forgotten the silent server's claim.
  EXPECT_FALSE(a.caught_up());
  EXPECT_EQ(a.log(kA)->max_known(), 5);
  cluster.net().faults().Heal();
  cluster.Run(3000);
  EXPECT_TRUE(a.caught_up());
  EXPECT_EQ(a.live_feature_count(), 5u);
  EXPECT_EQ(a.Digest(), cluster.at(kServer).Digest());
  EXPECT_EQ(cluster.at(kB).Digest(), cluster.at(kServer).Digest());
}

}  // namespace
}  // namespace dt
