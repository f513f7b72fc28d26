// Tests the status reply's anti-entropy lines: diverged, diverged_since_ms and one line per open
// difference, from when a difference is found until it is repaired.
#include <gtest/gtest.h>

#include <functional>

#include <fmt/format.h>

#include "engine/memory_change_store.h"
#include "runtime/process_runtime.h"
#include "runtime/status_report.h"
#include "simulation/sim_cluster.h"

namespace dt {
namespace {

bool RunUntil(testing::SimCluster& cluster, int64_t limit_ms, const std::function<bool()>& done) {
  for (int64_t t = 0; !done(); t += 10) {
    if (t >= limit_ms) return false;
    cluster.Run(10);
  }
  return true;
}

TEST(StatusTextTest, ShowsADivergenceFromWhenItIsFoundUntilItIsRepaired) {
  ReplicaConfig rc;
  rc.max_feature_period_ms = 200;
  rc.silence_ms = 800;
  rc.playback_retry_ms = 300;
  rc.playback_window = 64;
  rc.anti_entropy_period_ms = 500;
  const NodeAddress server{1, 100}, a{1, 1}, b{1, 2};
  MemoryChangeStore store;
  testing::SimCluster cluster(1, HeightGrid(33, 4.0, 10.0f), rc);
  cluster.Start(server, NodeRole::kServer, &store);
  Replica& author = cluster.Start(a, NodeRole::kNode);
  Replica& node = cluster.Start(b, NodeRole::kNode);
  cluster.Run(1000);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(author.Create(FeatureParams::Crater(30 + 20 * i, 50, 3)));
  cluster.Run(1000);
  PduBusConfig bus;
  bus.exercise_id = 1;
  bus.local = {9, 9};
  bus.terrain_size_x_m = bus.terrain_size_z_m = 128.0;
  const ProcessTransport transport = StackTransport(cluster.net().Join({9, 9}, 1), {}, 1, bus);
  auto status = [&] { return StatusText("node-2", NodeRole::kNode, node, transport, {}); };
  EXPECT_NE(status().find("\ncaught_up 1\ndiverged 0\ndiverged_since_ms -1\n"), std::string::npos)
      << status();

  Change bad = *node.log(a)->Find(2);
  bad.params.length_m[0] += 1.0;
  ASSERT_TRUE(node.anti_entropy().Overwrite(bad).ok());
  ASSERT_TRUE(RunUntil(cluster, 1000, [&] { return node.diverged(); }));
  const std::string text = status();
  EXPECT_NE(text.find(fmt::format("\ncaught_up 0\ndiverged 1\ndiverged_since_ms {}\n",
                                  node.diverged_since_ms())),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\ndivergence 1:1 with "), std::string::npos) << text;
  // The text reads back as a report and writes back byte for byte.
  Result<StatusReport> report = StatusReport::Parse(text);
  ASSERT_TRUE(report) << report.error().message << "\n" << text;
  EXPECT_EQ(report.value().ToText(), text);
  EXPECT_TRUE(report.value().diverged);
  EXPECT_EQ(report.value().diverged_since_ms, node.diverged_since_ms());
  EXPECT_FALSE(report.value().divergences.empty());
  EXPECT_TRUE(report.value().other_lines.empty()) << text;

  ASSERT_TRUE(RunUntil(cluster, 2000, [&] { return !node.diverged(); }));
  EXPECT_NE(status().find("\ndiverged 0\ndiverged_since_ms -1\n"), std::string::npos) << status();
  EXPECT_EQ(status().find("\ndivergence "), std::string::npos) << status();
}

}  // namespace
}  // namespace dt
