// Tests the observer role (docs/protocol.md, "Observers"): a replica that holds the terrain,
// creates nothing and is not counted by anyone: no sign-on waits for it, nobody asks it for
// playback, its own changes and claims about it are refused.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;
// The lowest address of the exercise: it would be the authority among nodes if it were one.
const NodeAddress kView{1, 0};

ReplicaConfig Defaults() {
  ReplicaConfig c = testing::TestReplicaConfig();
  c.members = {{kServer, NodeRole::kServer},
               {kA, NodeRole::kNode},
               {kB, NodeRole::kNode},
               {kView, NodeRole::kObserver}};
  return c;
}

class ObserverTest : public ::testing::Test, public testing::ServerAndTwoNodes {
 protected:
  explicit ObserverTest(const ReplicaConfig& config = Defaults()) : ServerAndTwoNodes(5, config) {}

  // A's next change (its second) reaches the observer, and whoever else is in `with`, alone; then
  // A crashes and the network heals. The observer holds A:2, the server does not.
  void AuthorCrashesAfterAChangeOnlyTheObserverGot(std::vector<NodeAddress> with = {}) {
    ASSERT_TRUE(A().Create(FeatureParams::Crater(30, 30, 2)).ok());
    Run(1000);
    ASSERT_EQ(cluster_.at(kView).Digest(), S().Digest());
    with.push_back(kA);
    with.push_back(kView);
    std::vector<NodeAddress> others;
    for (NodeAddress n : {kServer, kB}) {
      if (std::find(with.begin(), with.end(), n) == with.end()) others.push_back(n);
    }
    cluster_.net().faults().Partition(with, others);
    auto lost = A().Create(FeatureParams::Crater(90, 90, 3));
    ASSERT_TRUE(lost.ok());
    lost_ = lost.value();
    Run(100);
    ASSERT_NE(cluster_.at(kView).log(kA)->Find(2), nullptr);
    cluster_.Crash(kA);
    cluster_.net().faults().Heal();
  }

  // Runs until the observer has dropped a change, at most `ms`; the virtual time it took.
  int64_t RunUntilDropped(int64_t ms) {
    const int64_t start = cluster_.now_ms();
    while (cluster_.at(kView).anti_entropy().stats().slots_dropped == 0 &&
           cluster_.now_ms() - start < ms) {
      Run(10);
    }
    return cluster_.now_ms() - start;
  }

  FeatureId lost_;

  // A playback request as an observer sends one while it catches up, addressed to `target`.
  static dtpdu::playback_t Request(NodeAddress target, NodeAddress subject) {
    dtpdu::playback_t p{};
    p.requesting = ToPdu(kView);
    p.transmitting = ToPdu(target);
    p.subject = ToPdu(subject);
    p.range_kind = static_cast<uint8_t>(PlaybackRange::kChangeSeqs);
    p.start = 1;
    p.end = 1;
    return p;
  }

  // Runs the cluster and hands what arrived to the test's own buses too.
  void Run(int64_t ms) {
    for (int64_t t = 0; t < ms; t += 10) {
      cluster_.Run(10);
      for (auto& b : buses_) (void)b->HandleTimeout(0);
    }
  }
};

TEST_F(ObserverTest, ALateObserverHoldsTheTerrainSendsNoReportsAndCreatesNothing) {
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(A().Create(FeatureParams::Crater(20 + 10 * i, 30, 2)).ok());
    ASSERT_TRUE(B().Create(FeatureParams::Crater(30, 20 + 10 * i, 2)).ok());
  }
  Run(500);
  std::set<NodeAddress> reporters;
  BusAs({1, 50}).Subscribe<dtpdu::max_feature_t>(
      [&](const dtpdu::max_feature_t& m) { reporters.insert(FromPdu(m.sender)); });
  Replica& view = cluster_.Start(kView, NodeRole::kObserver);
  EXPECT_TRUE(view.signed_on());  // it listens at once: nothing of its own to learn
  Run(2000);
  EXPECT_TRUE(view.caught_up());
  EXPECT_EQ(view.live_feature_count(), 10u);
  EXPECT_EQ(view.Digest(), S().Digest());
  EXPECT_EQ(reporters.count(kView), 0u);
  EXPECT_EQ(reporters.count(kA), 1u);  // the listener does hear reports
  EXPECT_FALSE(view.Create(FeatureParams::Crater(60, 60, 2)).ok());
  EXPECT_FALSE(view.Destroy(S().terrain().FeaturesById().front()->id()).ok());
  EXPECT_EQ(view.counters().sent, 0u);
  // Later changes reach it live.
  ASSERT_TRUE(A().Create(FeatureParams::Crater(90, 90, 2)).ok());
  Run(300);
  EXPECT_EQ(view.live_feature_count(), 11u);
  EXPECT_EQ(view.Digest(), S().Digest());
}

// An observer compares the others' summaries with its own logs and takes the authority's copy of
// a slot it holds differently; nobody takes its copy, since it sends no summaries of its own.
TEST_F(ObserverTest, AnObserverRepairsItsOwnCopyAndNobodyTakesIt) {
  Replica& view = cluster_.Start(kView, NodeRole::kObserver);
  ASSERT_TRUE(A().Create(FeatureParams::Crater(40, 40, 3)).ok());
  Run(1000);
  ASSERT_EQ(view.Digest(), S().Digest());
  Change bad = *view.log(kA)->Find(1);
  bad.params.length_m[0] += 0.5;
  ASSERT_TRUE(view.anti_entropy().Overwrite(bad).ok());
  ASSERT_NE(view.Digest(), S().Digest());
  Run(3000);
  EXPECT_EQ(view.Digest(), S().Digest());
  EXPECT_FALSE(view.diverged());
  EXPECT_GE(view.anti_entropy().stats().slots_repaired, 1u);
  for (Replica* r : {&A(), &B(), &S()}) {
    EXPECT_EQ(r->anti_entropy().stats().slots_repaired, 0u) << r->config().address.ToString();
    EXPECT_EQ(r->anti_entropy().stats().differences_found, 0u) << r->config().address.ToString();
  }
}

// A node signing on waits for every replica it hears; an observer asking for playback the whole
// time must not be one of them (it never answers), or the node never signs on.
TEST_F(ObserverTest, ANodeSigningOnDoesNotWaitForAnObserverItHears) {
  ASSERT_TRUE(A().Create(FeatureParams::Crater(30, 30, 2)).ok());
  Run(300);
  cluster_.Crash(kB);
  Run(300);
  PduBus& view = BusAs(kView);
  Replica& b = cluster_.Start(kB, NodeRole::kNode);
  for (int i = 0; i < 20 && !b.signed_on(); ++i) {
    ASSERT_TRUE(view.Publish(Request(kA, kA)).ok());
    Run(200);
  }
  EXPECT_TRUE(b.signed_on());
  EXPECT_TRUE(A().counters().played_back > 0);  // the observer's requests are answered
}

// A replica with a gap asks the author, servers, then any live peer: never an observer, which
// does not answer. B learns that A made a change only A holds, then A and the server are gone:
// a retry would go to the next live candidate, and the observer asking for playback meanwhile
// must not be one.
TEST_F(ObserverTest, AnObserverIsNeverAskedForPlayback) {
  cluster_.Crash(kServer);
  cluster_.Crash(kA);
  std::set<NodeAddress> asked;
  BusAs({1, 50}).Subscribe<dtpdu::playback_t>([&](const dtpdu::playback_t& p) {
    if (!p.is_response && FromPdu(p.requesting) == kB) asked.insert(FromPdu(p.transmitting));
  });
  PduBus& view = BusAs(kView);
  dtpdu::max_feature_t claim{};
  claim.subject = ToPdu(kA);
  claim.max_feature_number = 1;
  claim.max_change_seq = 1;
  claim.lamport = 1;
  claim.role = static_cast<uint8_t>(NodeRole::kNode);
  testing::StampTestGround(claim);
  ASSERT_TRUE(BusAs(kA).Publish(claim).ok());  // A's last report, then A is gone
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(view.Publish(Request(kB, kB)).ok());
    Run(100);
  }
  EXPECT_EQ(asked.count(kA), 1u);  // B did have a gap and asked the author
  EXPECT_EQ(asked.count(kView), 0u);
}

TEST_F(ObserverTest, AChangeByAnObserverAndAClaimAboutOneAreRefused) {
  PduBus& view = BusAs(kView);
  FeaturePdu f;
  f.id = {kView.site, kView.host, 1};
  f.params = FeatureParams::Crater(60, 60, 4);
  f.change.changed_by = kView;
  f.change.change_seq = 1;
  f.change.lamport = 5;
  ASSERT_TRUE(view.Publish(ToConstruct(f)).ok());
  dtpdu::max_feature_t claim{};
  claim.subject = ToPdu(kView);
  claim.max_feature_number = 7;
  claim.max_change_seq = 7;
  claim.lamport = 5;
  claim.role = static_cast<uint8_t>(NodeRole::kServer);
  testing::StampTestGround(claim);
  ASSERT_TRUE(BusAs({1, 51}).Publish(claim).ok());  // no member: refused as a stranger anyway
  Run(300);
  for (Replica* r : {&A(), &B(), &S()}) {
    EXPECT_EQ(r->live_feature_count(), 0u) << r->config().address.ToString();
    EXPECT_GE(r->counters().refused_role, 1u) << r->config().address.ToString();
    EXPECT_EQ(r->log(kView), nullptr);
    EXPECT_TRUE(r->caught_up());
  }
}

// A change of A reached the observer alone, then A crashed. A's next incarnation signs on
// without it (nobody else holds it, and an observer answers no one): once A's own summary holds
// less, the observer drops its copy, and its terrain is the exercise's again.
TEST_F(ObserverTest, AChangeOnlyTheObserverGotIsDroppedOnceItsAuthorsNextIncarnationHoldsLess) {
  Replica& view = cluster_.Start(kView, NodeRole::kObserver);
  ASSERT_NO_FATAL_FAILURE(AuthorCrashesAfterAChangeOnlyTheObserverGot());
  Run(2000);
  // Nobody else holds it, but A is down: the observer waits for A's word (gap_give_up_ms is
  // 30 s here).
  EXPECT_NE(view.Digest(), S().Digest());
  EXPECT_EQ(view.anti_entropy().stats().slots_dropped, 0u);
  ASSERT_EQ(view.live_feature_count(), 2u);
  Replica& a = cluster_.Start(kA, NodeRole::kNode);
  RunUntilDropped(8000);
  EXPECT_EQ(view.anti_entropy().stats().slots_dropped, 1u);
  EXPECT_EQ(view.log(kA)->max_held(), 1);
  EXPECT_EQ(view.log(kA)->Find(2), nullptr);
  EXPECT_EQ(view.records().Find(lost_), nullptr);
  EXPECT_EQ(view.live_feature_count(), 1u);
  EXPECT_EQ(view.Digest(), S().Digest());
  Run(2000);
  EXPECT_TRUE(view.caught_up());
  EXPECT_EQ(view.Digest(), S().Digest());
  EXPECT_EQ(view.counters().sent, 0u);  // its copy never travelled
  EXPECT_TRUE(a.signed_on());
  EXPECT_EQ(a.own_change_seq(), 1);
  for (Replica* r : {&a, &B(), &S()}) {
    EXPECT_EQ(r->anti_entropy().stats().slots_dropped, 0u) << r->config().address.ToString();
  }
}

ReplicaConfig GivingUpAfter4s() {
  ReplicaConfig c = Defaults();
  c.gap_give_up_ms = 4000;
  return c;
}

class ObserverGivingUpTest : public ObserverTest {
 protected:
  ObserverGivingUpTest() : ObserverTest(GivingUpAfter4s()) {}
};

// The same, but A never comes back: nobody has reported the slot for gap_give_up_ms, so the
// observer drops it, as a gap nobody can fill would be given up on.
TEST_F(ObserverGivingUpTest, AChangeOnlyTheObserverGotIsDroppedWhenItsAuthorStaysSilent) {
  Replica& view = cluster_.Start(kView, NodeRole::kObserver);
  ASSERT_NO_FATAL_FAILURE(AuthorCrashesAfterAChangeOnlyTheObserverGot());
  const int64_t took = RunUntilDropped(12000);
  EXPECT_EQ(view.anti_entropy().stats().slots_dropped, 1u);
  EXPECT_GE(took, 4000);  // not before the slot went unreported for gap_give_up_ms
  EXPECT_EQ(view.log(kA)->max_held(), 1);
  EXPECT_EQ(view.live_feature_count(), 1u);
  EXPECT_EQ(view.Digest(), S().Digest());
  Run(1000);
  EXPECT_TRUE(view.caught_up());
  EXPECT_EQ(view.Digest(), S().Digest());
}

// B holds A's lost change too, but B is unheard (its writes fail) when A's next incarnation
// holds less: the observer drops its copy on a stale view. B's next summaries report the slot,
// the observer fetches it as any gap, and everyone, the server included, ends with B's copy.
TEST_F(ObserverTest, ADropMadeWhileAHolderWasUnheardHealsWhenItIsHeardAgain) {
  Replica& view = cluster_.Start(kView, NodeRole::kObserver);
  ASSERT_NO_FATAL_FAILURE(AuthorCrashesAfterAChangeOnlyTheObserverGot({kB}));
  ASSERT_NE(B().log(kA)->Find(2), nullptr);
  const Change held = *B().log(kA)->Find(2);
  const int64_t blocked_ms = 9000;
  cluster_.net().BlockWrites(kB, cluster_.now_ms() + blocked_ms);
  cluster_.Start(kA, NodeRole::kNode);
  const int64_t took = RunUntilDropped(blocked_ms);
  ASSERT_EQ(view.anti_entropy().stats().slots_dropped, 1u);
  ASSERT_LT(took, blocked_ms);  // B was still unheard
  EXPECT_EQ(view.log(kA)->Find(2), nullptr);
  Run(blocked_ms - took + 4000);
  ASSERT_NE(view.log(kA)->Find(2), nullptr);
  EXPECT_EQ(*view.log(kA)->Find(2), held);
  ASSERT_NE(S().log(kA)->Find(2), nullptr);
  EXPECT_EQ(*S().log(kA)->Find(2), held);
  EXPECT_EQ(view.anti_entropy().stats().slots_dropped, 1u);  // dropped once, not again
  EXPECT_EQ(view.live_feature_count(), 2u);
  EXPECT_EQ(view.Digest(), S().Digest());
  EXPECT_EQ(view.Digest(), B().Digest());
  EXPECT_TRUE(view.caught_up());
}

}  // namespace
}  // namespace dt
