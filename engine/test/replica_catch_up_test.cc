// Tests a rejoining replica's catch-up across a simulated WAN and LAN: the playback window grows
// with a long round trip, never past its bound, and stays at its base on a LAN.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "engine/test/replica_test_config.h"
#include "simulation/sim_cluster.h"
#include "transport/pdu_bus.h"

namespace dt {
namespace {

using testing::SimCluster;

constexpr NodeAddress kServer = testing::kTestServer;  // site 1
constexpr NodeAddress kA = testing::kTestA;            // site 1
constexpr NodeAddress kFarB{2, 2};                     // site 2
constexpr NodeAddress kTap{2, 9};                      // the test's ear on site 2
constexpr int64_t kChanges = 2048;
constexpr int kMaxWindow = 512;

ReplicaConfig Config(int window_max) {
  ReplicaConfig c = testing::TestReplicaConfig();  // playback_window 64
  c.playback_window_max = window_max;
  return c;
}
constexpr int kWindow = 64;

struct CatchUp {
  int64_t took_ms = -1;  // from the heal until B holds all of A's changes; -1: not in 20 s
  int64_t widest_request = 0;
  int64_t requests = 0;
  bool equal = false;  // B's digest is A's and B is caught up, a second later
};

// The server and A on site 1, B on site 2, every copy between the sites `delay_ms` late. B is cut
// off while A makes kChanges changes, then B's catch-up is timed and its requests heard.
CatchUp RunCatchUp(int64_t delay_ms, int window_max) {
  FaultConfig faults;
  faults.other_site_min_delay = faults.other_site_max_delay = delay_ms;
  MemoryChangeStore store;
  SimCluster cluster(3, testing::TestGround(), Config(window_max), faults);
  cluster.Start(kServer, NodeRole::kServer, &store);
  Replica& a = cluster.Start(kA, NodeRole::kNode);
  Replica& b = cluster.Start(kFarB, NodeRole::kNode);
  auto transport = cluster.net().Join(kTap, 1);
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = kTap;
  bc.terrain_size_x_m = bc.terrain_size_z_m = 128.0;
  bc.clock = [] { return 0u; };
  PduBus tap(*transport, bc);
  CatchUp out;
  tap.Subscribe<dtpdu::playback_t>([&](const dtpdu::playback_t& p) {
    if (p.is_response || FromPdu(p.requesting) != kFarB) return;
    out.widest_request = std::max(out.widest_request, p.end - p.start + 1);
    ++out.requests;
  });
  auto run = [&](int64_t ms) {
    for (int64_t t = 0; t < ms; t += 10) {
      cluster.Run(10);
      (void)tap.HandleTimeout(0);
    }
  };
  run(2000);
  EXPECT_TRUE(a.signed_on() && b.signed_on());
  cluster.net().faults().Isolate(kFarB);
  for (int n = 0; n < kChanges; ++n) {
    const FeatureParams crater =
        FeatureParams::Crater(10 + (n % 25) * 4, 10 + (n / 25) % 25 * 4, 1);
    // A node holds at most a window of changes the server has not acknowledged.
    for (int waits = 0; !a.Create(crater).ok(); ++waits) {
      if (waits == 50) {
        ADD_FAILURE() << "A cannot create change " << n;
        return out;
      }
      run(100);
    }
  }
  run(500);
  out.requests = 0;
  out.widest_request = 0;
  cluster.net().faults().Heal();
  const int64_t healed_ms = cluster.now_ms();
  for (int64_t t = 0; t < 20000; t += 10) {
    if (b.log(kA) != nullptr && b.log(kA)->contiguous() == a.own_change_seq()) {
      out.took_ms = cluster.now_ms() - healed_ms;
      break;
    }
    run(10);
  }
  run(1000);
  out.equal = b.Digest() == a.Digest() && b.caught_up();
  return out;
}

TEST(CatchUpTest, AcrossAWanTheWindowGrowsToItsBoundAndTheCatchUpTakesFewRoundTrips) {
  ASSERT_EQ(Config(kMaxWindow).playback_window, kWindow);
  const int64_t delay_ms = 50;
  // A fixed window (as before it adapted) moves one window per round trip: 32 of 100 ms.
  const CatchUp fixed = RunCatchUp(delay_ms, kWindow);
  ASSERT_GE(fixed.took_ms, 0);
  EXPECT_TRUE(fixed.equal);
  EXPECT_EQ(fixed.widest_request, kWindow);
  EXPECT_GE(fixed.took_ms, kChanges / kWindow * 2 * delay_ms);
  // Growing (64, 128, 256, then 512 a time) takes 7.
  const CatchUp grown = RunCatchUp(delay_ms, kMaxWindow);
  ASSERT_GE(grown.took_ms, 0);
  EXPECT_TRUE(grown.equal);
  EXPECT_EQ(grown.widest_request, kMaxWindow);
  std::printf(
      "catch-up of %d changes, 100 ms round trips: fixed window %lld ms (%lld requests), "
      "grown %lld ms (%lld requests)\n",
      static_cast<int>(kChanges), static_cast<long long>(fixed.took_ms),
      static_cast<long long>(fixed.requests), static_cast<long long>(grown.took_ms),
      static_cast<long long>(grown.requests));
  EXPECT_LT(grown.took_ms, fixed.took_ms / 2)
      << grown.requests << " requests against " << fixed.requests;
}

TEST(CatchUpTest, OnALanTheWindowStaysAtItsBase) {
  const CatchUp c = RunCatchUp(0, kMaxWindow);
  ASSERT_GE(c.took_ms, 0);
  EXPECT_TRUE(c.equal);
  EXPECT_EQ(c.widest_request, kWindow);
  EXPECT_GE(c.requests, kChanges / kWindow);
}

}  // namespace
}  // namespace dt
