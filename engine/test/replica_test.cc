// Tests Replica over a simulated network: commands, propagation, gap detection and playback,
// sign-on, concurrent edits, the standby and store failures.
#include "engine/replica.h"

#include <gtest/gtest.h>

#include "engine/change_hash.h"
#include "engine/memory_change_store.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kStandby = testing::kTestStandby;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;

ReplicaConfig Defaults() { return testing::TestReplicaConfig(); }

class ReplicaTest : public ::testing::Test, public testing::ServerAndTwoNodes {
 protected:
  ReplicaTest() : ServerAndTwoNodes(1, Defaults()) {}
};

TEST_F(ReplicaTest, ACreatedFeatureReachesEveryReplica) {
  ASSERT_TRUE(A().signed_on());
  auto id = A().Create(FeatureParams::Crater(40, 40, 5));
  ASSERT_TRUE(id.ok()) << id.error().message;
  // A node skips a window of numbers when it signs on (docs/protocol.md).
  EXPECT_EQ(id.value(), (FeatureId{1, 1, 65}));
  cluster_.Run(100);
  ASSERT_NE(B().terrain().Find(id.value()), nullptr);
  EXPECT_EQ(B().Digest(), A().Digest());
  EXPECT_EQ(S().Digest(), A().Digest());
  EXPECT_EQ(B().max_feature_known().at(kA), 65);
}

TEST_F(ReplicaTest, ANodeHoldsAtMostAWindowOfUnacknowledgedChanges) {
  cluster_.Crash(kServer);
  int accepted = 0;
  for (int i = 0; i < 100; ++i) {
    if (A().Create(FeatureParams::Crater(10 + i, 40, 1)).ok()) ++accepted;
  }
  EXPECT_EQ(accepted, 64);
  Replica& s = cluster_.Start(kServer, NodeRole::kServer, &store_);
  cluster_.Run(1500);
  EXPECT_EQ(s.live_feature_count(), 64u);
  EXPECT_EQ(A().acknowledged_change_seq(), 64);
  EXPECT_TRUE(A().Create(FeatureParams::Crater(10, 80, 1)).ok());
}

TEST_F(ReplicaTest, BadCommandsReturnAnErrorAndChangeNothing) {
  auto id = A().Create(FeatureParams::Crater(40, 40, 5));
  ASSERT_TRUE(id.ok());
  const std::string digest = A().Digest();
  const auto sent = A().counters().sent;
  const auto seq = A().own_change_seq();
  EXPECT_FALSE(A().Create(FeatureParams::Crater(40, 40, -1)).ok());             // invalid
  EXPECT_FALSE(A().Create(FeatureParams::Crater(127, 127, 9)).ok());            // off the terrain
  EXPECT_FALSE(A().Modify({1, 1, 77}, FeatureParams::Crater(40, 40, 5)).ok());  // unknown
  EXPECT_FALSE(A().Modify(id.value(), FeatureParams::Berm(40, 40, 0, 10, 3, 2)).ok());  // type
  EXPECT_FALSE(A().Breach(id.value(), 1.0, 2.0).ok());  // not a berm
  ASSERT_TRUE(A().Destroy(id.value()).ok());
  const std::string after_destroy = A().Digest();
  const auto seq_after_destroy = A().own_change_seq();
  EXPECT_FALSE(A().Destroy(id.value()).ok());
  EXPECT_FALSE(A().Modify(id.value(), FeatureParams::Crater(41, 40, 5)).ok());
  EXPECT_EQ(A().Digest(), after_destroy);
  EXPECT_NE(after_destroy, digest);
  EXPECT_EQ(A().counters().sent, sent + 1);
  EXPECT_EQ(seq_after_destroy, seq + 1);
  EXPECT_EQ(A().own_change_seq(), seq_after_destroy);
  // Numbers are not consumed by refused commands.
  auto next = A().Create(FeatureParams::Crater(60, 60, 5));
  ASSERT_TRUE(next.ok());
  EXPECT_EQ(next.value().number, id.value().number + 1);
}

TEST_F(ReplicaTest, ABreachReplacesTheBermByItsPiecesEverywhere) {
  auto berm = A().Create(FeatureParams::Berm(30, 60, 0.0, 60, 6, 3));
  ASSERT_TRUE(berm.ok());
  cluster_.Run(100);
  auto pieces = B().Breach(berm.value(), 25.0, 10.0);
  ASSERT_TRUE(pieces.ok()) << pieces.error().message;
  EXPECT_EQ(pieces.value().size(), 2u);
  cluster_.Run(100);
  EXPECT_EQ(A().terrain().Find(berm.value()), nullptr);
  for (FeatureId p : pieces.value()) EXPECT_NE(A().terrain().Find(p), nullptr);
  EXPECT_EQ(A().Digest(), B().Digest());
  EXPECT_EQ(A().Digest(), S().Digest());
}

TEST_F(ReplicaTest, ANodeThatHasNotSignedOnRefusesToCreate) {
  cluster_.Crash(kA);
  Replica& a = cluster_.Start(kA, NodeRole::kNode);
  EXPECT_FALSE(a.signed_on());
  EXPECT_FALSE(a.Create(FeatureParams::Crater(40, 40, 5)).ok());
}

TEST_F(ReplicaTest, AGapIsDetectedAndPlayedBackByTheAuthor) {
  cluster_.net().faults().Isolate(kB);
  for (int i = 0; i < 40; ++i) {
    ASSERT_TRUE(A().Create(FeatureParams::Crater(10 + 2 * i, 40, 1)).ok());
  }
  cluster_.Run(100);
  EXPECT_EQ(B().live_feature_count(), 0u);
  cluster_.net().faults().Heal();
  cluster_.Run(1500);
  EXPECT_EQ(B().live_feature_count(), 40u);
  EXPECT_EQ(B().Digest(), A().Digest());
  EXPECT_TRUE(B().caught_up());
  EXPECT_GE(A().counters().played_back, 40u);
}

TEST_F(ReplicaTest, EarthMovesTravelAsChangesAndArePlayedBack) {
  ASSERT_GT(A().terrain().ground().posts_x(), 12);
  ASSERT_GT(A().terrain().ground().posts_z(), 12);
  cluster_.net().faults().Isolate(kB);
  std::vector<FeatureId> ids;
  for (int i = 0; i < 20; ++i) {
    auto id =
        A().Create(FeatureParams::EarthMove({{static_cast<uint16_t>(2 + i % 8), 5, -200 - i},
                                             {static_cast<uint16_t>(2 + i % 8), 6, 200 + i}}));
    ASSERT_TRUE(id.ok()) << id.error().message;
    ids.push_back(id.value());
  }
  // Blade work is added once: no update of it.
  const Status update = A().Modify(ids[0], FeatureParams::EarthMove({{2, 5, 7}}));
  ASSERT_FALSE(update.ok());
  EXPECT_NE(update.error().message.find("cannot be updated"), std::string::npos);
  cluster_.Run(100);
  EXPECT_EQ(B().terrain().BladeDeltaMm(2, 5), 0);
  cluster_.net().faults().Heal();
  cluster_.Run(1500);
  EXPECT_EQ(B().Digest(), A().Digest());
  EXPECT_EQ(S().Digest(), A().Digest());
  EXPECT_EQ(B().terrain().BladeDeltaMm(2, 5), A().terrain().BladeDeltaMm(2, 5));
  EXPECT_EQ(A().terrain().BladeDeltaMm(2, 5), -200 - 208 - 216);
  EXPECT_GE(A().counters().played_back, 20u);
  // The logged change, through its PDU and back, is the same change.
  const Change* logged = A().log(kA)->Find(1);
  ASSERT_NE(logged, nullptr);
  ASSERT_EQ(logged->params.type, FeatureType::kEarthMove);
  auto back = FromEarthMove(ToEarthMove(ToFeaturePdu(*logged)));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(ChangeFrom(back.value(), ChangeKind::kConstruct), *logged);
  // Anti-entropy tells copies differing in one post's millimetre apart.
  Change other = *logged;
  other.params.post_deltas[1].delta_mm += 1;
  EXPECT_NE(ChangeHash(other), ChangeHash(*logged));
  other = *logged;
  other.params.post_deltas[1].j += 1;
  EXPECT_NE(ChangeHash(other), ChangeHash(*logged));
  // A destroyed earth move is taken off every ground.
  ASSERT_TRUE(B().Destroy(ids[0]).ok());
  cluster_.Run(300);
  EXPECT_EQ(A().terrain().BladeDeltaMm(2, 5), -208 - 216);
  EXPECT_EQ(B().Digest(), A().Digest());
}

TEST_F(ReplicaTest, ACatchUpAsksForTheNextWindowWhenAnAnswerCompletesOneNotAtTheNextTick) {
  cluster_.net().faults().Isolate(kB);
  const int windows = 8;
  for (int w = 0; w < windows; ++w) {
    for (int i = 0; i < Defaults().playback_window; ++i) {
      const int n = w * Defaults().playback_window + i;
      ASSERT_TRUE(A().Create(FeatureParams::Crater(10 + (n % 25) * 4, 10 + (n / 25) % 25 * 4, 1)));
    }
    cluster_.Run(300);  // the server acknowledges: A's window is free again
  }
  const int64_t total = A().own_change_seq();
  cluster_.net().faults().Heal();
  // Ticks until B has asked for and received its first window.
  for (int t = 0; t < 100 && (B().log(kA) == nullptr || B().log(kA)->contiguous() == 0); ++t) {
    cluster_.Run(10);
  }
  ASSERT_NE(B().log(kA), nullptr);
  const int64_t before = B().log(kA)->contiguous();
  ASSERT_GT(before, 0);
  ASSERT_LT(before, total);
  // No tick from here on: every further window is asked for from inside B's handler.
  cluster_.Deliver(200);
  EXPECT_EQ(B().log(kA)->contiguous(), total);
  EXPECT_EQ(B().Digest(), A().Digest());
}

TEST_F(ReplicaTest, UpdatesAndDestructsAreRecoveredToo) {
  auto id = A().Create(FeatureParams::Crater(40, 40, 5));
  auto other = A().Create(FeatureParams::Crater(80, 80, 5));
  ASSERT_TRUE(id.ok() && other.ok());
  cluster_.Run(100);
  cluster_.net().faults().Isolate(kB);
  ASSERT_TRUE(A().Modify(id.value(), FeatureParams::Crater(44, 40, 6)).ok());
  ASSERT_TRUE(A().Destroy(other.value()).ok());
  cluster_.Run(100);
  EXPECT_NE(B().Digest(), A().Digest());
  cluster_.net().faults().Heal();
  cluster_.Run(1000);
  EXPECT_EQ(B().Digest(), A().Digest());
  EXPECT_EQ(B().records().Find(id.value())->params, FeatureParams::Crater(44, 40, 6));
  EXPECT_TRUE(B().records().Find(other.value())->destroyed);
}

TEST_F(ReplicaTest, PlaybackGoesToTheServerWhenTheAuthorIsSilent) {
  cluster_.net().faults().Isolate(kB);
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(A().Create(FeatureParams::Crater(10 + 4 * i, 50, 1)).ok());
  }
  cluster_.Run(300);
  const std::string digest = A().Digest();
  cluster_.Crash(kA);
  cluster_.net().faults().Heal();
  cluster_.Run(3000);
  EXPECT_EQ(B().Digest(), digest);
  EXPECT_EQ(S().Digest(), digest);
  EXPECT_GE(S().counters().played_back, 20u);
}

TEST_F(ReplicaTest, SignOnReturnsTheLastIdSoNoneIsIssuedTwice) {
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(A().Create(FeatureParams::Crater(20 + 10 * i, 20, 2)).ok());
  cluster_.Run(600);
  EXPECT_EQ(A().acknowledged_change_seq(), 3);
  const int64_t last = A().own_feature_number();
  cluster_.Crash(kA);
  cluster_.Run(200);
  Replica& a = cluster_.Start(kA, NodeRole::kNode);
  cluster_.Run(1000);
  ASSERT_TRUE(a.signed_on());
  // It learned its last number and skipped a window past it: even features it created but
  // nobody acknowledged cannot be reissued.
  EXPECT_EQ(a.own_feature_number(), last + 64);
  EXPECT_EQ(a.own_change_seq(), 3);
  auto id = a.Create(FeatureParams::Crater(80, 80, 3));
  ASSERT_TRUE(id.ok());
  EXPECT_EQ(id.value().number, static_cast<uint32_t>(last + 65));
  cluster_.Run(500);
  // The rejoined node caught up on its own earlier changes too.
  EXPECT_EQ(a.live_feature_count(), 4u);
  EXPECT_EQ(a.Digest(), B().Digest());
}

TEST_F(ReplicaTest, ConcurrentEditsOfOneFeatureResolveIdentically) {
  auto id = A().Create(FeatureParams::Crater(40, 40, 5));
  ASSERT_TRUE(id.ok());
  cluster_.Run(100);
  cluster_.net().faults().Partition({kA}, {kB});
  ASSERT_TRUE(A().Modify(id.value(), FeatureParams::Crater(40, 40, 7)).ok());
  ASSERT_TRUE(B().Modify(id.value(), FeatureParams::Crater(40, 40, 3)).ok());
  cluster_.Run(100);
  cluster_.net().faults().Heal();
  cluster_.Run(1000);
  EXPECT_EQ(A().Digest(), B().Digest());
  EXPECT_EQ(A().Digest(), S().Digest());
  // Equal clocks: the higher changing node, B, wins.
  EXPECT_EQ(A().records().Find(id.value())->params, FeatureParams::Crater(40, 40, 3));
}

TEST_F(ReplicaTest, TheServerReportsDurableOnlyAfterTheStoreCommitted) {
  store_.set_fail_appends(true);
  ASSERT_TRUE(A().Create(FeatureParams::Crater(40, 40, 5)).ok());
  cluster_.Run(600);
  EXPECT_EQ(A().acknowledged_change_seq(), 0);
  EXPECT_FALSE(S().store_status().ok());
  EXPECT_EQ(S().live_feature_count(), 1u);  // held, not durable
  store_.set_fail_appends(false);
  cluster_.Run(600);
  EXPECT_TRUE(S().store_status().ok());
  EXPECT_EQ(A().acknowledged_change_seq(), 1);
  EXPECT_EQ(store_.size(), 1u);
}

TEST_F(ReplicaTest, ARestartedServerResumesFromItsStoreAndRequestsWhatItMissed) {
  ASSERT_TRUE(A().Create(FeatureParams::Crater(40, 40, 5)).ok());
  cluster_.Run(300);
  cluster_.Crash(kServer);
  ASSERT_TRUE(A().Create(FeatureParams::Crater(60, 60, 5)).ok());
  cluster_.Run(300);
  Replica& s = cluster_.Start(kServer, NodeRole::kServer, &store_);
  EXPECT_EQ(s.live_feature_count(), 1u);  // from the store
  cluster_.Run(1500);
  EXPECT_EQ(s.live_feature_count(), 2u);
  EXPECT_EQ(s.Digest(), A().Digest());
  EXPECT_EQ(A().acknowledged_change_seq(), 2);
}

TEST(ReplicaStandbyTest, TheStandbyAnswersWhenThePrimaryIsSilent) {
  MemoryChangeStore primary_store, standby_store;
  SimCluster cluster(2, HeightGrid(33, 4.0, 10.0f), Defaults());
  cluster.Start(kServer, NodeRole::kServer, &primary_store);
  cluster.Start(kStandby, NodeRole::kStandby, &standby_store);
  cluster.Start(kA, NodeRole::kNode);
  cluster.Start(kB, NodeRole::kNode);
  cluster.Run(1000);
  cluster.net().faults().Isolate(kB);
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(cluster.at(kA).Create(FeatureParams::Crater(10 + 8 * i, 30, 2)).ok());
  }
  cluster.Run(500);
  const std::string digest = cluster.at(kA).Digest();
  const int64_t last = cluster.at(kA).own_feature_number();
  EXPECT_EQ(standby_store.size(), 10u);
  cluster.Crash(kA);
  cluster.Crash(kServer);
  cluster.net().faults().Heal();
  cluster.Run(4000);
  EXPECT_EQ(cluster.at(kB).Digest(), digest);
  EXPECT_GE(cluster.at(kStandby).counters().played_back, 10u);
  // A rejoining node learns its last number from the standby.
  Replica& a = cluster.Start(kA, NodeRole::kNode);
  cluster.Run(1000);
  ASSERT_TRUE(a.signed_on());
  EXPECT_EQ(a.own_feature_number(), last + 64);
}

}  // namespace
}  // namespace dt
