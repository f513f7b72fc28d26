#include "node/scenario.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "node/scenario_runner.h"
#include "runtime/test/map_actions.h"

namespace dt {
namespace {

std::string ErrorOf(const std::string& text, int vehicles = 1) {
  try {
    ParseScenario(text, "s.toml", vehicles);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

const char* kScenario = R"(
[[step]]
action = "drive"
vehicle = 0
speed_mps = 5
heading_rate_deg_s = 0
duration_s = 3

[[step]]
at_s = 1.0
action = "crater"
name = "c"
x_m = 50
z_m = 60
radius_m = 4

[[step]]
action = "berm"
name = "b"
x_m = 100
z_m = 100
direction_deg = 0
length_m = 40
width_m = 4
height_m = 2

[[step]]
at_s = 2.0
action = "update"
target = "c"
radius_m = 7

[[step]]
action = "wait"
duration_s = 0.5

[[step]]
action = "breach"
target = "b"
gap_start_m = 10
gap_width_m = 5

[[step]]
at_s = 4.0
action = "destroy"
target = "b.2"
)";

TEST(ScenarioTest, ParsesTimesInOrder) {
  const Scenario s = ParseScenario(kScenario, "s.toml", 1);
  // drive, crater, berm, update, wait, breach, drive-stop (3 s), destroy
  ASSERT_EQ(s.steps.size(), 8u);
  EXPECT_EQ(s.steps[0].action, ScenarioAction::kDrive);
  EXPECT_DOUBLE_EQ(s.steps[1].at_s, 1.0);
  EXPECT_DOUBLE_EQ(s.steps[2].at_s, 1.0);  // no at_s: with the step before
  EXPECT_EQ(s.steps[3].action, ScenarioAction::kUpdate);
  EXPECT_DOUBLE_EQ(s.steps[4].at_s, 2.5);  // after the wait
  EXPECT_EQ(s.steps[5].action, ScenarioAction::kBreach);
  EXPECT_DOUBLE_EQ(s.steps[5].at_s, 2.5);
  EXPECT_EQ(s.steps[6].action, ScenarioAction::kDrive);
  EXPECT_DOUBLE_EQ(s.steps[6].at_s, 3.0);
  EXPECT_DOUBLE_EQ(s.steps[6].speed_mps, 0.0);
  EXPECT_DOUBLE_EQ(s.end_s(), 4.0);
  EXPECT_DOUBLE_EQ(s.steps[1].params.length_m[0], 4.0);
}

TEST(ScenarioTest, RunnerPlaysStepsAsTimePasses) {
  ScenarioRunner runner(ParseScenario(kScenario, "s.toml", 1));
  MapActions node;
  EXPECT_EQ(runner.Advance(0.5, node), 1);  // the drive only
  ASSERT_EQ(node.drives.size(), 1u);
  EXPECT_DOUBLE_EQ(node.drives[0].speed_mps, 5.0);
  EXPECT_TRUE(node.features.empty());

  EXPECT_EQ(runner.Advance(1.0, node), 2);
  EXPECT_EQ(node.features.size(), 2u);
  const FeatureId crater = runner.names().at("c");
  EXPECT_DOUBLE_EQ(node.features.at(crater).length_m[0], 4.0);

  runner.Advance(2.9, node);
  EXPECT_DOUBLE_EQ(node.features.at(crater).length_m[0], 7.0);
  EXPECT_EQ(runner.names().count("b"), 0u);
  ASSERT_EQ(runner.names().count("b.2"), 1u);
  EXPECT_EQ(node.features.size(), 3u);  // crater + two pieces

  runner.Advance(10.0, node);
  EXPECT_TRUE(runner.done());
  EXPECT_EQ(runner.failed(), 0);
  EXPECT_EQ(node.features.size(), 2u);
  ASSERT_EQ(node.drives.size(), 2u);
  EXPECT_DOUBLE_EQ(node.drives[1].speed_mps, 0.0);
}

TEST(ScenarioTest, RunTimeFailureIsCountedAndSkipped) {
  ScenarioRunner runner(ParseScenario(kScenario, "s.toml", 1));
  MapActions node;
  runner.Advance(1.0, node);
  node.features.erase(runner.names().at("c"));  // as if another node destroyed it
  runner.Advance(10.0, node);
  EXPECT_TRUE(runner.done());
  EXPECT_EQ(runner.failed(), 1);
  ASSERT_EQ(runner.errors().size(), 1u);
  EXPECT_NE(runner.errors()[0].find("s.toml step 4"), std::string::npos) << runner.errors()[0];
}

TEST(ScenarioTest, RefusesBadScenariosBeforeRunning) {
  const std::string base = "[[step]]\naction = \"crater\"\nname = \"c\"\nx_m = 5\nz_m = 5\n";
  EXPECT_NE(ErrorOf(base).find("needs radius_m"), std::string::npos) << ErrorOf(base);
  EXPECT_NE(ErrorOf(base + "radius_m = -1\n").find("s.toml: step[0]: crater radius_m = -1"),
            std::string::npos)
      << ErrorOf(base + "radius_m = -1\n");
  EXPECT_NE(ErrorOf(base + "radius_m = 2\nheight_m = 1\n").find("height_m is not a key"),
            std::string::npos)
      << ErrorOf(base + "radius_m = 2\nheight_m = 1\n");
  const std::string ok = base + "radius_m = 2\n";
  EXPECT_EQ(ErrorOf(ok), "");
  EXPECT_NE(ErrorOf(ok + ok).find("\"c\" is already used"), std::string::npos);
  EXPECT_NE(ErrorOf(ok + "[[step]]\naction = \"destroy\"\ntarget = \"d\"\n").find("step[1].target"),
            std::string::npos);
  const std::string destroyed = ok + "[[step]]\naction = \"destroy\"\ntarget = \"c\"\n";
  EXPECT_EQ(ErrorOf(destroyed), "");
  EXPECT_NE(ErrorOf(destroyed + "[[step]]\naction = \"update\"\ntarget = \"c\"\nradius_m = 3\n")
                .find("no longer exists"),
            std::string::npos);
  EXPECT_NE(ErrorOf(ok + "[[step]]\naction = \"breach\"\ntarget = \"c\"\ngap_start_m = 1\n"
                         "gap_width_m = 1\n")
                .find("needs a berm"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"drive\"\nvehicle = 1\nspeed_mps = 1\n", 1)
                .find("has 1 vehicle"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\nat_s = 5\naction = \"wait\"\nduration_s = 1\n"
                    "[[step]]\nat_s = 2\naction = \"wait\"\nduration_s = 1\n")
                .find("goes back in time"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"dance\"\n").find("value 'dance'"), std::string::npos)
      << ErrorOf("[[step]]\naction = \"dance\"\n");
  EXPECT_NE(ErrorOf("[[step]]\naction = \"wait\"\nduration_s = 1\nextra = 2\n")
                .find("step[0].extra: unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[steps]]\naction = \"wait\"\n").find("steps: unknown key"),
            std::string::npos);
}

TEST(ScenarioTest, DitchesLinesAndAreasTakePointsAndSoil) {
  const Scenario s = ParseScenario(R"(
[[step]]
action = "ditch"
name = "d"
side_run_m = 1
points = [[10, 10, 2, 5], [40, 10, 2, 5]]

[[step]]
action = "update"
target = "d"
"points[2].x_m" = 60
"points[2].z_m" = 30
"points[2].height_m" = 1.5
"points[2].width_m" = 4

[[step]]
action = "breach"
target = "d"
gap_start_m = 20
gap_width_m = 4

[[step]]
action = "area"
name = "a"
soil = "water"
level_m = 2
points = [[10, 50], [30, 50], [20, 70]]
)",
                                   "s.toml", 1);
  ASSERT_EQ(s.steps.size(), 4u);
  EXPECT_EQ(s.steps[0].params.type, FeatureType::kDitch);
  EXPECT_EQ(s.steps[0].params.points.size(), 2u);
  EXPECT_EQ(s.steps[0].params.x_m, 10.0);
  EXPECT_EQ(s.steps[1].edit.values.size(), 4u);
  EXPECT_EQ(s.steps[3].params.material, Material::kWater);
  EXPECT_EQ(s.steps[3].params.height_m[0], 2.0);
  EXPECT_EQ(s.steps[3].params.points[2], (FeaturePoint{20, 70, 0, 0}));
  // Bad points and soils are refused naming the field.
  const std::string ditch = "[[step]]\naction = \"ditch\"\nname = \"d\"\nside_run_m = 1\n";
  EXPECT_NE(ErrorOf(ditch + "points = [[10, 10, 2, 1], [40, 10, 2, 5]]\n")
                .find("ditch points[0].width_m = 1 is less than twice the side run"),
            std::string::npos)
      << ErrorOf(ditch + "points = [[10, 10, 2, 1], [40, 10, 2, 5]]\n");
  EXPECT_NE(ErrorOf(ditch + "points = [[10, 10, 2], [40, 10, 2, 5]]\n")
                .find("row 0 must be an array of 4 numbers"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"area\"\nname = \"a\"\nsoil = \"lava\"\n"
                    "points = [[1, 1], [5, 1], [3, 4]]\n")
                .find("step[0].soil: is not a soil"),
            std::string::npos)
      << ErrorOf(
             "[[step]]\naction = \"area\"\nname = \"a\"\nsoil = \"lava\"\n"
             "points = [[1, 1], [5, 1], [3, 4]]\n");
}

TEST(ScenarioTest, SpawnAndRemoveChangeWhichVehicleIndicesExist) {
  const std::string spawn =
      "[[step]]\naction = \"spawn\"\ntype = \"jeep\"\nx_m = 10\nz_m = 20\nheading_deg = 90\n"
      "model = \"light\"\n";
  const std::string drive1 = "[[step]]\naction = \"drive\"\nvehicle = 1\nspeed_mps = 1\n";
  const std::string remove0 = "[[step]]\naction = \"remove\"\nvehicle = 0\n";
  EXPECT_NE(ErrorOf(drive1).find("has 1 vehicle"), std::string::npos);
  EXPECT_EQ(ErrorOf(spawn + drive1), "");
  EXPECT_NE(ErrorOf(spawn + remove0 + drive1).find("has 1 vehicle"), std::string::npos);
  EXPECT_NE(ErrorOf(remove0 + remove0).find("0 vehicle(s) at this step"), std::string::npos)
      << ErrorOf(remove0 + remove0);
  EXPECT_NE(ErrorOf(spawn + "[[step]]\naction = \"spawn\"\nx_m = 1\nz_m = 1\nmodel = \"x\"\n")
                .find("step[1].model"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"spawn\"\nx_m = 1\n").find("z_m"), std::string::npos);

  const Scenario sc = ParseScenario(spawn + remove0, "s.toml", 1);
  ASSERT_EQ(sc.steps.size(), 2u);
  EXPECT_EQ(sc.steps[0].action, ScenarioAction::kSpawn);
  EXPECT_EQ(sc.steps[0].spawn.type, "jeep");
  EXPECT_EQ(sc.steps[0].spawn.model, "light");
  EXPECT_NEAR(sc.steps[0].spawn.heading_rad, 1.5707963267948966, 1e-12);
  struct Fleet : MapActions {
    std::vector<std::string> calls;
    Result<int> Spawn(const SpawnRequest& r) override {
      calls.push_back("spawn " + r.type);
      return 1;
    }
    Status Remove(int index) override {
      calls.push_back("remove " + std::to_string(index));
      return Status::Ok();
    }
  } fleet;
  ScenarioRunner runner(sc);
  runner.Advance(0.0, fleet);
  EXPECT_EQ(fleet.calls, (std::vector<std::string>{"spawn jeep", "remove 0"}));
  EXPECT_EQ(runner.failed(), 0);
}

TEST(ScenarioTest, BladeStepsLowerAndRaiseABlade) {
  const std::string down = "[[step]]\naction = \"blade\"\nvehicle = 0\ndepth_m = 0.25\n";
  const std::string up = "[[step]]\naction = \"blade\"\nvehicle = 0\nposition = \"up\"\n";
  EXPECT_NE(ErrorOf(down, 0).find("0 vehicle(s) at this step"), std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"blade\"\nvehicle = 0\nposition = \"left\"\n")
                .find("step[0].position"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"blade\"\nvehicle = 0\n").find("depth_m"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[[step]]\naction = \"blade\"\nvehicle = 0\ndepth_m = -1\n").find("depth_m"),
            std::string::npos);
  const Scenario sc = ParseScenario(down + up, "s.toml", 1);
  ASSERT_EQ(sc.steps.size(), 2u);
  EXPECT_EQ(sc.steps[0].action, ScenarioAction::kBlade);
  EXPECT_EQ(sc.steps[0].blade_depth_m, 0.25);
  EXPECT_FALSE(sc.steps[1].blade_depth_m.has_value());
  struct Dozer : MapActions {
    std::vector<std::string> calls;
    Status SetBlade(int index, std::optional<double> depth_m) override {
      calls.push_back(fmt::format("blade {} {}", index, depth_m ? *depth_m : -1.0));
      return Status::Ok();
    }
  } dozer;
  ScenarioRunner runner(sc);
  runner.Advance(0.0, dozer);
  EXPECT_EQ(dozer.calls, (std::vector<std::string>{"blade 0 0.25", "blade 0 -1"}));
  EXPECT_EQ(runner.failed(), 0);
}

TEST(ScenarioTest, ShippedScenariosParse) {
  const std::filesystem::path dir = std::filesystem::path(DT_SOURCE_DIR) / "configs/scenarios";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(LoadScenario(entry.path(), 1)) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 3);
}

}  // namespace
}  // namespace dt
