// Tests of the 3D view's terrain window and the loop's answering of the web server's questions.
#include "view/terrain_window.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include <nlohmann/json.hpp>

#include "terrain/bridge.h"
#include "vehicle/bridge_solids.h"
#include "view/loop_requests.h"

namespace dt {
namespace {

// 257 posts 4 m apart (1024 m), with a crater 3 m deep, a berm, an intact and a destroyed bridge.
Terrain MakeTerrain() {
  std::vector<float> posts;
  for (int j = 0; j < 257; ++j)
    for (int i = 0; i < 257; ++i) posts.push_back(static_cast<float>(10.0 + 0.01 * i + 0.02 * j));
  Terrain t(HeightGrid(257, 4.0, std::move(posts), Material::kDirt));
  EXPECT_TRUE(t.Add({1, 1, 1}, FeatureParams::DeepCrater(300, 300, 12, 3)).ok());
  EXPECT_TRUE(t.Add({1, 1, 2}, FeatureParams::Berm(500, 300, 0.5, 30, 4, 2)).ok());
  EXPECT_TRUE(t.Add({1, 1, 3}, FeatureParams::Bridge(300, 600, 0.0, 10, 30, 40, 30, 6, 6)).ok());
  FeatureParams broken = FeatureParams::Bridge(700, 600, 1.0, 10, 30, 40, 30, 6, 6);
  broken.status = BridgeStatus::kDestroyed;
  EXPECT_TRUE(t.Add({1, 1, 4}, broken).ok());
  return t;
}

TEST(TerrainWindowTest, SamplesTheSurfaceWithEarthworksAtTheAskedStep) {
  const Terrain t = MakeTerrain();
  const auto w = nlohmann::json::parse(TerrainWindowJson(t, {300, 300, 64, 33}));
  EXPECT_EQ(w["step"].get<double>(), 4.0);  // 128 m over 32 steps: the post spacing
  ASSERT_EQ(w["nx"].get<int>(), 33);
  ASSERT_EQ(w["nz"].get<int>(), 33);
  const double x0 = w["x0"], z0 = w["z0"];
  EXPECT_LE(x0, 300 - 64 + 4);
  double deepest = 0.0, highest = 0.0;
  for (int j = 0; j < 33; ++j) {
    for (int i = 0; i < 33; ++i) {
      const double x = x0 + 4.0 * i, z = z0 + 4.0 * j;
      EXPECT_NEAR(w["h"][j * 33 + i].get<double>(), t.ElevationAt(x, z), 0.006) << x << "," << z;
      EXPECT_NEAR(w["d"][j * 33 + i].get<double>(), t.ElevationAt(x, z) - t.GroundElevationAt(x, z),
                  0.011);
      deepest = std::min(deepest, w["d"][j * 33 + i].get<double>());
      highest = std::max(highest, w["d"][j * 33 + i].get<double>());
    }
  }
  EXPECT_LT(deepest, -1.0) << "the crater's floor shows as a cut";
  EXPECT_GT(highest, 0.5) << "its rim as a raise";
  EXPECT_TRUE(w["solids"].empty()) << "no bridge meets this window";
}

TEST(TerrainWindowTest, AWindowBeyondTheTerrainIsTheTerrainAtItsOwnStep) {
  const Terrain t = MakeTerrain();
  const auto w = nlohmann::json::parse(TerrainWindowJson(t, {512, 512, 5000, 129}));
  EXPECT_EQ(w["step"].get<double>(), 8.0);  // 1024 m on the terrain over 128 steps
  EXPECT_EQ(w["x0"].get<double>(), 0.0);
  EXPECT_EQ(w["nx"].get<int>(), 129);
  EXPECT_EQ(w["h"].size(), 129u * 129u);
}

TEST(TerrainWindowTest, ALargeTerrainIsSentAtACoarserStepNeverMorePosts) {
  const Terrain t(HeightGrid(2049, 4.0, 5.0f, Material::kDirt));  // 8 km
  const auto w = nlohmann::json::parse(TerrainWindowJson(t, {4096, 4096, 4096, 129}));
  EXPECT_EQ(w["step"].get<double>(), 64.0);  // ceil(8192 m / 128 steps / 4 m) = 16 posts
  EXPECT_EQ(w["nx"].get<int>(), 129);
  EXPECT_EQ(w["nz"].get<int>(), 129);
  const auto near = nlohmann::json::parse(TerrainWindowJson(t, {4000, 4000, 100, 129}));
  // Close up, finer than the posts: 200 m over 128 steps is 1.56 m, so half the 4 m spacing.
  EXPECT_EQ(near["step"].get<double>(), 2.0);
  EXPECT_EQ(near["x0"].get<double>(), 3900.0);
  EXPECT_EQ(near["nx"].get<int>(), 101);
  const auto closest = nlohmann::json::parse(TerrainWindowJson(t, {4000, 4000, 10, 129}));
  EXPECT_EQ(closest["step"].get<double>(), 0.5) << "an eighth of the spacing at most";
}

TEST(TerrainWindowTest, BridgesAreTheSolidsVehiclesMeet) {
  const Terrain t = MakeTerrain();
  const auto w = nlohmann::json::parse(TerrainWindowJson(t, {500, 600, 300, 129}));
  std::vector<Solid> expected;
  for (FeatureId id : {FeatureId{1, 1, 3}, FeatureId{1, 1, 4}}) {
    for (const Solid& s : BridgeSolids(*static_cast<const Bridge*>(t.Find(id)), t.ground()))
      expected.push_back(s);
  }
  ASSERT_EQ(w["solids"].size(), expected.size());
  int rubble = 0;
  for (size_t k = 0; k < expected.size(); ++k) {
    const auto& s = w["solids"][k];
    EXPECT_EQ(s["top"][0].get<double>(), expected[k].top0_m);
    EXPECT_EQ(s["bottom"][1].get<double>(), expected[k].bottom1_m);
    EXPECT_EQ(s["a"][1].get<double>(), expected[k].a1_m);
    EXPECT_EQ(s["o"][0].get<double>(), expected[k].origin_x_m);
    rubble += s["kind"] == "rubble";
  }
  EXPECT_EQ(rubble, 1) << "the destroyed bridge's span lies as rubble";
}

TEST(TerrainWindowTest, QueriesAreCheckedWithTheValueNamed) {
  auto r = ParseTerrainWindowQuery("x=10&z=20.5&half=100&posts=65");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().z_m, 20.5);
  EXPECT_EQ(r.value().posts, 65);
  EXPECT_EQ(ParseTerrainWindowQuery("x=10&z=20").error().message,
            "/terrain3d: \"x=10&z=20\" lacks x, z or half");
  EXPECT_NE(ParseTerrainWindowQuery("x=nan&z=1&half=2").error().message.find("x=\"nan\""),
            std::string::npos);
  EXPECT_NE(ParseTerrainWindowQuery("x=1&z=1&half=2&posts=9999").error().message.find("9999"),
            std::string::npos);
  EXPECT_NE(ParseTerrainWindowQuery("x=1&z=1&half=-2").error().message.find("-2"),
            std::string::npos);
  EXPECT_NE(ParseTerrainWindowQuery("x=1&z=1&half=2&y=3").error().message.find("\"y\""),
            std::string::npos);
}

TEST(LoopRequestsTest, AQuestionIsAnsweredOnTheLoop) {
  LoopRequests q;
  std::thread asker([&] {
    auto a = q.Ask("x", 10000);
    ASSERT_TRUE(a.has_value());
    EXPECT_EQ(*a, "answer to x");
  });
  while (q.waiting() == 0) std::this_thread::yield();
  q.Serve([](const std::string& s) { return "answer to " + s; }, 4);
  asker.join();
  EXPECT_EQ(q.waiting(), 0u);
}

TEST(LoopRequestsTest, UnansweredInTimeIsNothingAndLeavesNoQuestion) {
  LoopRequests q;
  EXPECT_FALSE(q.Ask("x", 1).has_value());
  EXPECT_EQ(q.waiting(), 0u);
}

}  // namespace
}  // namespace dt
