// Tests anti-entropy over a simulated network: a slot held differently is found within a summary
// period and repaired everywhere by the repair rule, located in log_32 rounds in a long log, and
// nothing but summaries is sent while the logs agree.
#include "engine/anti_entropy.h"

#include <functional>

#include <gtest/gtest.h>

#include "engine/change_hash.h"
#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "pdu/pdu_traits.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;
constexpr NodeAddress kStandby = testing::kTestStandby;
constexpr NodeAddress kA = testing::kTestA;
constexpr NodeAddress kB = testing::kTestB;
const NodeAddress kC{1, 3};
constexpr int kPeriodMs = 500;

ReplicaConfig Defaults() {
  ReplicaConfig c;
  c.max_feature_period_ms = 200;
  c.silence_ms = 800;
  c.playback_retry_ms = 300;
  c.playback_window = 64;
  c.anti_entropy_period_ms = kPeriodMs;
  return c;
}

// Runs `cluster` in 10 ms steps until `done` or `limit_ms` passed; the virtual time it took, or -1.
int64_t RunUntil(SimCluster& cluster, int64_t limit_ms, const std::function<bool()>& done) {
  const int64_t start = cluster.now_ms();
  while (!done()) {
    if (cluster.now_ms() - start >= limit_ms) return -1;
    cluster.Run(10);
  }
  return cluster.now_ms() - start;
}

bool AllAgree(SimCluster& cluster) {
  const auto live = cluster.live();
  for (NodeAddress a : live) {
    Replica& r = cluster.at(a);
    if (r.diverged() || !r.caught_up() || r.Digest() != cluster.at(live.front()).Digest()) {
      return false;
    }
  }
  return true;
}

// The replica's copy of `author`'s change `seq` with other parameters (a corrupted copy).
Change Corrupted(const Replica& r, NodeAddress author, int64_t seq) {
  const ChangeLog* log = r.log(author);
  if (log == nullptr || log->Find(seq) == nullptr) std::abort();
  Change c = *log->Find(seq);
  c.params.length_m[0] += 1.5;  // a crater's radius
  return c;
}

const Change& Held(const Replica& r, NodeAddress author, int64_t seq) {
  return *r.log(author)->Find(seq);
}

class AntiEntropyTest : public ::testing::Test, public testing::ServerAndTwoNodes {
 protected:
  AntiEntropyTest() : ServerAndTwoNodes(1, Defaults()) {
    for (int i = 0; i < 20; ++i) {
      if (!A().Create(FeatureParams::Crater(10 + 5 * i, 40, 2)).ok()) std::abort();
    }
    cluster_.Run(1000);
  }
};

TEST_F(AntiEntropyTest, OneSlotHeldDifferentlyIsFoundWithinAPeriodAndRepairedToEqualDigests) {
  ASSERT_TRUE(AllAgree(cluster_));
  const std::string digest = S().Digest();
  ASSERT_TRUE(B().anti_entropy().Overwrite(Corrupted(B(), kA, 7)).ok());
  EXPECT_NE(B().Digest(), digest);
  EXPECT_TRUE(B().caught_up());  // nothing tells a gap here: only the summaries can

  const int64_t found_ms = RunUntil(cluster_, 2 * kPeriodMs, [&] { return B().diverged(); });
  ASSERT_GE(found_ms, 0) << "not found";
  EXPECT_LE(found_ms, kPeriodMs + 20);
  // Diverged means not caught up, and says since when, with whom, in whose log.
  EXPECT_FALSE(B().caught_up());
  EXPECT_GE(B().diverged_since_ms(), 0);
  ASSERT_FALSE(B().divergences().empty());
  EXPECT_EQ(B().divergences().front().author, kA);

  const int64_t repaired_ms = RunUntil(cluster_, 4 * kPeriodMs, [&] { return AllAgree(cluster_); });
  ASSERT_GE(repaired_ms, 0) << "not repaired";
  EXPECT_EQ(B().Digest(), digest);
  EXPECT_EQ(Held(B(), kA, 7), Held(S(), kA, 7));
  EXPECT_EQ(B().diverged_since_ms(), -1);
  EXPECT_EQ(B().anti_entropy().stats().slots_repaired, 1u);
  EXPECT_EQ(A().anti_entropy().stats().slots_repaired, 0u);
  EXPECT_EQ(S().anti_entropy().stats().slots_repaired, 0u);
}

TEST_F(AntiEntropyTest, TheServersCopyWinsOverTheAuthorsOwn) {
  // The author's own copy differs: the server's (what it acknowledged) is kept.
  const Change server_copy = Held(S(), kA, 5);
  ASSERT_TRUE(A().anti_entropy().Overwrite(Corrupted(A(), kA, 5)).ok());
  ASSERT_GE(RunUntil(cluster_, 4 * kPeriodMs, [&] { return AllAgree(cluster_); }), 0);
  EXPECT_EQ(Held(A(), kA, 5), server_copy);
  EXPECT_EQ(Held(B(), kA, 5), server_copy);
  EXPECT_EQ(A().anti_entropy().stats().slots_repaired, 1u);

  // The server's copy differs (its memory corrupted, as a bad store would): the author and
  // everyone else take it, even over the author's own.
  const Change bad = Corrupted(S(), kA, 9);
  ASSERT_TRUE(S().anti_entropy().Overwrite(bad).ok());
  ASSERT_GE(RunUntil(cluster_, 4 * kPeriodMs, [&] { return AllAgree(cluster_); }), 0);
  EXPECT_EQ(Held(A(), kA, 9), bad);
  EXPECT_EQ(Held(B(), kA, 9), bad);
  EXPECT_EQ(S().anti_entropy().stats().slots_repaired, 0u);
  EXPECT_EQ(A().anti_entropy().stats().slots_repaired, 2u);
}

TEST_F(AntiEntropyTest, NothingButSummariesIsSentWhileTheLogsAgree) {
  ASSERT_TRUE(AllAgree(cluster_));
  cluster_.Run(10 * kPeriodMs);
  // A summary of one author's log (A's: nobody else made a change).
  dtpdu::anti_entropy_t one{};
  one.entries.resize(1);
  one.num_entries = 1;
  const auto summary_bytes = static_cast<uint64_t>(EncodePdu(one).size());
  for (NodeAddress a : cluster_.live()) {
    const AntiEntropy::Stats& s = cluster_.at(a).anti_entropy().stats();
    EXPECT_GE(s.summaries_sent, 10u) << a.ToString();
    EXPECT_GE(s.summaries_received, 20u) << a.ToString();
    EXPECT_EQ(s.hash_requests_sent, 0u) << a.ToString();
    EXPECT_EQ(s.hash_answers_sent, 0u) << a.ToString();
    EXPECT_EQ(s.copy_requests_sent, 0u) << a.ToString();
    EXPECT_EQ(s.copies_sent, 0u) << a.ToString();
    EXPECT_EQ(s.differences_found, 0u) << a.ToString();
    EXPECT_EQ(s.bytes_sent, s.summaries_sent * summary_bytes) << a.ToString();
    EXPECT_FALSE(cluster_.at(a).diverged());
  }
}

TEST(AntiEntropyStoreTest, AStandbyStoresTheRepairedCopyInPlaceOfItsOwn) {
  MemoryChangeStore primary_store, standby_store;
  SimCluster cluster(2, HeightGrid(33, 4.0, 10.0f), Defaults());
  Replica& s = cluster.Start(kServer, NodeRole::kServer, &primary_store);
  cluster.Start(kStandby, NodeRole::kStandby, &standby_store);
  Replica& a = cluster.Start(kA, NodeRole::kNode);
  cluster.Run(1000);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(a.Create(FeatureParams::Crater(20 + 10 * i, 60, 3)).ok());
  cluster.Run(1000);
  ASSERT_TRUE(AllAgree(cluster));
  // The standby's stored copy of A:3 is corrupted, and so is the one it loaded from it.
  Change* stored = standby_store.Find(kA, 3);
  ASSERT_NE(stored, nullptr);
  const Change bad = Corrupted(cluster.at(kStandby), kA, 3);
  *stored = bad;
  ASSERT_TRUE(cluster.at(kStandby).anti_entropy().Overwrite(bad).ok());
  ASSERT_GE(RunUntil(cluster, 4 * kPeriodMs, [&] { return AllAgree(cluster); }), 0);
  EXPECT_EQ(*standby_store.Find(kA, 3), Held(s, kA, 3));  // the server's copy won (rank)
  EXPECT_EQ(Held(a, kA, 3), Held(s, kA, 3));
  // Restarted from its store, the standby holds the repaired copy.
  cluster.Crash(kStandby);
  Replica& t = cluster.Start(kStandby, NodeRole::kStandby, &standby_store);
  EXPECT_EQ(Held(t, kA, 3), Held(s, kA, 3));
  EXPECT_EQ(t.Digest(), s.Digest());
}

// Two nodes, no server: the author A made `n` updates of one crater.
class LongLogTest : public ::testing::Test {
 protected:
  static ReplicaConfig Config() {
    ReplicaConfig c = Defaults();
    c.require_server = false;
    c.playback_window = static_cast<int>(kMaxPlaybackSpan);
    return c;
  }
  LongLogTest() : cluster_(3, HeightGrid(33, 4.0, 10.0f), Config()) {}
  void Make(NodeAddress other, int n) {
    cluster_.Start(kA, NodeRole::kNode);
    cluster_.Start(other, NodeRole::kNode);
    cluster_.Run(1500);
    auto id = cluster_.at(kA).Create(FeatureParams::Crater(60, 60, 3));
    if (!id) std::abort();
    for (int i = 1; i < n; ++i) {
      const double r = 2 + (i % 7) * 0.5;
      if (!cluster_.at(kA).Modify(id.value(), FeatureParams::Crater(60, 60, r)).ok()) std::abort();
      if (i % 1000 == 0) cluster_.Run(10);
    }
    cluster_.Run(1000);
  }
  SimCluster cluster_;
};

TEST_F(LongLogTest, ADifferenceDeepInTenThousandChangesIsLocatedInLog32Rounds) {
  constexpr int kChanges = 10000;
  Make(kB, kChanges);
  Replica& a = cluster_.at(kA);
  Replica& b = cluster_.at(kB);
  ASSERT_EQ(b.log(kA)->contiguous(), kChanges);
  ASSERT_TRUE(AllAgree(cluster_));
  // B's copy of update 6789 takes a clock past every other: it is the last writer on B.
  Change bad = Held(b, kA, 6789);
  bad.stamp.lamport += 1000000;
  ASSERT_TRUE(b.anti_entropy().Overwrite(bad).ok());
  ASSERT_NE(b.Digest(), a.Digest());
  ASSERT_GE(RunUntil(cluster_, 4 * kPeriodMs, [&] { return AllAgree(cluster_); }), 0);
  EXPECT_EQ(Held(b, kA, 6789), Held(a, kA, 6789));  // the author's copy won over another's
  // Each side located the slot in ceil(log_32 10^4) = 3 rounds of one hash request each.
  for (Replica* r : {&a, &b}) {
    const AntiEntropy::Stats& s = r->anti_entropy().stats();
    EXPECT_LE(s.hash_requests_sent, 3u) << r->config().address.ToString();
    EXPECT_LE(s.copy_requests_sent, 2u) << r->config().address.ToString();
  }
  EXPECT_GT(
      a.anti_entropy().stats().hash_requests_sent + b.anti_entropy().stats().hash_requests_sent,
      0u);
  EXPECT_EQ(b.anti_entropy().stats().slots_repaired, 1u);
  EXPECT_EQ(a.anti_entropy().stats().slots_repaired, 0u);
}

TEST_F(LongLogTest, WithoutServerOrAuthorTheLowerHashWinsOnBothSides) {
  Make(kB, 30);
  cluster_.Start(kC, NodeRole::kNode);
  cluster_.Run(2000);
  ASSERT_TRUE(AllAgree(cluster_));
  cluster_.Crash(kA);  // the author is gone: B and C are both "other" holders
  cluster_.Run(3000);
  Replica& b = cluster_.at(kB);
  Replica& c = cluster_.at(kC);
  const Change original = Held(b, kA, 12);
  const Change bad = Corrupted(b, kA, 12);
  ASSERT_TRUE(b.anti_entropy().Overwrite(bad).ok());
  // Update 12 is not the last writer: the terrain never differed, only the logs did.
  ASSERT_GE(RunUntil(cluster_, 4 * kPeriodMs,
                     [&] { return Held(b, kA, 12) == Held(c, kA, 12) && AllAgree(cluster_); }),
            0);
  const Change& kept = ChangeHash(bad) < ChangeHash(original) ? bad : original;
  EXPECT_EQ(Held(b, kA, 12), kept);
  EXPECT_EQ(Held(c, kA, 12), kept);
}

}  // namespace
}  // namespace dt
