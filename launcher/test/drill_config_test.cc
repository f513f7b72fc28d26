#include "launcher/drill_config.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "runtime/exercise_config.h"

namespace dt {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParseDrillConfig(text, "d.toml", "/base");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

const std::string kHead = "[drill]\nname = \"x\"\nexercise = \"e.toml\"\ndeadline_s = 30\n";

TEST(DrillConfigTest, ReadsTimelineInTimeOrder) {
  const DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\nat_s = 5\ndo = \"kill\"\ntargets = \"node-2\"\n"
          "[[action]]\nat_s = 1\ndo = \"random_ops\"\ncount = 20\nduration_s = 6\nseed = 3\n"
          "[[action]]\nat_s = 2\ndo = \"partition\"\ntargets = [\"node-1\"]\n"
          "from = [\"node-2\", \"node-3\"]\n"
          "[[action]]\nat_s = 2\ndo = \"loss\"\ndrop_probability = 0.3\n",
      "d.toml", "/base");
  EXPECT_EQ(d.exercise, std::filesystem::path("/base/e.toml"));
  EXPECT_DOUBLE_EQ(d.deadline_s, 30.0);
  ASSERT_EQ(d.actions.size(), 4u);
  EXPECT_EQ(d.actions[0].kind, DrillActionKind::kRandomOps);
  EXPECT_EQ(d.actions[0].count, 20);
  EXPECT_EQ(d.actions[0].seed, 3u);
  EXPECT_EQ(d.actions[1].kind, DrillActionKind::kPartition);  // stable among equal times
  EXPECT_EQ(d.actions[1].from.size(), 2u);
  EXPECT_EQ(d.actions[2].kind, DrillActionKind::kLoss);
  EXPECT_TRUE(d.actions[2].targets.empty());
  EXPECT_EQ(d.actions[3].targets, std::vector<std::string>{"node-2"});
}

TEST(DrillConfigTest, RefusesBadDrills) {
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"explode\"\n").find("action[0].do"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"kill\"\n").find("kill needs targets"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(kHead + "[[action]]\ndo = \"loss\"\ndrop_probability = 2\n").find("drop_probability"),
      std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\nat_s = 99\ndo = \"heal\"\n").find("at_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"heal\"\ncolour = 1\n").find("unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"kill\"\ntargets = [1]\n").find("strings"),
            std::string::npos);
}

TEST(DrillConfigTest, ReadsChaosWithDefaults) {
  const DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\ndo = \"chaos\"\nduration_s = 20\nseed = 9\n"
          "[[action]]\nat_s = 1\ndo = \"chaos\"\nduration_s = 20\nperiod_s = 4\nmax_down = 2\n"
          "down_min_s = 0.5\ndown_max_s = 2\ntargets = [\"server\", \"node-1\"]\n",
      "d.toml", "/base");
  ASSERT_EQ(d.actions.size(), 2u);
  const DrillAction& a = d.actions[0];
  EXPECT_EQ(a.kind, DrillActionKind::kChaos);
  EXPECT_DOUBLE_EQ(a.duration_s, 20.0);
  EXPECT_EQ(a.seed, 9u);
  EXPECT_DOUBLE_EQ(a.period_s, 10.0);
  EXPECT_EQ(a.max_down, 1);
  EXPECT_DOUBLE_EQ(a.down_min_s, 1.0);
  EXPECT_DOUBLE_EQ(a.down_max_s, 5.0);
  EXPECT_TRUE(a.targets.empty());
  const DrillAction& b = d.actions[1];
  EXPECT_DOUBLE_EQ(b.period_s, 4.0);
  EXPECT_EQ(b.max_down, 2);
  EXPECT_DOUBLE_EQ(b.down_min_s, 0.5);
  EXPECT_DOUBLE_EQ(b.down_max_s, 2.0);
  EXPECT_EQ(b.targets.size(), 2u);
}

TEST(DrillConfigTest, RefusesBadChaos) {
  const std::string chaos = "[[action]]\ndo = \"chaos\"\n";
  EXPECT_NE(ErrorOf(kHead + chaos).find("duration_s"), std::string::npos);
  EXPECT_NE(ErrorOf(kHead + chaos + "duration_s = 10\ndown_min_s = 3\ndown_max_s = 2\n")
                .find("below down_min_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + chaos + "at_s = 20\nduration_s = 20\n").find("after deadline_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + chaos + "duration_s = 10\nmax_down = 2\ntargets = \"node-1\"\n")
                .find("one target"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + chaos + "duration_s = 10\nperiod_s = 0\n").find("period_s"),
            std::string::npos);
}

TEST(DrillConfigTest, OneSeedReseedsEveryRandomAction) {
  DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\nat_s = 2\ndo = \"chaos\"\nduration_s = 5\nseed = 100\n"
          "[[action]]\nat_s = 0\ndo = \"random_ops\"\ncount = 5\nduration_s = 5\nseed = 200\n"
          "[[action]]\nat_s = 1\ndo = \"kill\"\ntargets = \"node-1\"\n",
      "d.toml", "/base");
  OverrideSeeds(d, 40);
  ASSERT_EQ(d.actions.size(), 3u);
  EXPECT_EQ(d.actions[0].kind, DrillActionKind::kRandomOps);
  EXPECT_EQ(d.actions[0].seed, 40u);
  EXPECT_EQ(d.actions[1].kind, DrillActionKind::kKill);
  EXPECT_EQ(d.actions[1].seed, 1u);  // untouched
  EXPECT_EQ(d.actions[2].kind, DrillActionKind::kChaos);
  EXPECT_EQ(d.actions[2].seed, 41u);
}

TEST(DrillConfigTest, ReadsVehicleActions) {
  const DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\nat_s = 3\ndo = \"vehicles_seen\"\nowner = \"node-1\"\nseen = false\n"
          "within_s = 8\nnot_before_s = 2\n"
          "[[action]]\nat_s = 4\ndo = \"sample_vehicles\"\nowner = \"node-1\"\n"
          "targets = \"node-3\"\nduration_s = 6\nmin_tilt_deg = 10\n"
          "[[action]]\nat_s = 5\ndo = \"sample_vehicles\"\nduration_s = 6\nperiod_s = 0.5\n"
          "error_m = 2\nmin_fraction = 0.8\n",
      "d.toml", "/base");
  ASSERT_EQ(d.actions.size(), 3u);
  EXPECT_EQ(d.actions[0].kind, DrillActionKind::kVehiclesSeen);
  EXPECT_EQ(d.actions[0].owner, "node-1");
  EXPECT_FALSE(d.actions[0].seen);
  EXPECT_DOUBLE_EQ(d.actions[0].within_s, 8.0);
  EXPECT_DOUBLE_EQ(d.actions[0].not_before_s, 2.0);
  EXPECT_EQ(d.actions[1].kind, DrillActionKind::kSampleVehicles);
  EXPECT_DOUBLE_EQ(d.actions[1].min_tilt_deg, 10.0);
  EXPECT_LT(d.actions[1].min_fraction, 0.0);  // unchecked
  EXPECT_DOUBLE_EQ(d.actions[1].period_s, 0.25);
  EXPECT_TRUE(d.actions[2].owner.empty());
  EXPECT_DOUBLE_EQ(d.actions[2].error_m, 2.0);
  EXPECT_DOUBLE_EQ(d.actions[2].min_fraction, 0.8);
  EXPECT_LT(d.actions[2].min_tilt_deg, 0.0);
}

TEST(DrillConfigTest, RefusesBadVehicleActions) {
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"vehicles_seen\"\n").find("owner"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"vehicles_seen\"\nowner = \"n\"\n"
                            "within_s = 2\nnot_before_s = 3\n")
                .find("not_before_s 3 is not below within_s 2"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"sample_vehicles\"\nduration_s = 5\n")
                .find("needs min_tilt_deg or min_fraction"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"sample_vehicles\"\nduration_s = 5\n"
                            "min_fraction = 1.5\n")
                .find("min_fraction"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\nat_s = 28\ndo = \"sample_vehicles\"\n"
                            "duration_s = 5\nmin_tilt_deg = 3\n")
                .find("ends after deadline_s"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"sample_vehicles\"\nduration_s = 5\n"
                            "min_tilt_deg = 3\nseen = true\n")
                .find("unknown key"),
            std::string::npos);
}

TEST(DrillConfigTest, ReadsVehicleReachesAndDigestMarks) {
  const DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\nat_s = 2\ndo = \"vehicle_reaches\"\nowner = \"node-2\"\nvehicle = 1\n"
          "x_min_m = 70\nz_min_m = 30\nz_max_m = 50\nwithin_s = 20\n"
          "[[action]]\nat_s = 3\ndo = \"digest\"\nmark = \"works\"\n",
      "d.toml", "/base");
  ASSERT_EQ(d.actions.size(), 2u);
  const DrillAction& v = d.actions[0];
  EXPECT_EQ(v.kind, DrillActionKind::kVehicleReaches);
  EXPECT_EQ(v.owner, "node-2");
  EXPECT_EQ(v.vehicle, 1);
  EXPECT_DOUBLE_EQ(v.x_min_m, 70.0);
  EXPECT_GT(v.x_max_m, 1e299);  // open on that side
  EXPECT_DOUBLE_EQ(v.z_min_m, 30.0);
  EXPECT_DOUBLE_EQ(v.z_max_m, 50.0);
  EXPECT_DOUBLE_EQ(v.within_s, 20.0);
  EXPECT_EQ(d.actions[1].kind, DrillActionKind::kDigest);
  EXPECT_EQ(d.actions[1].mark, "works");
  EXPECT_DOUBLE_EQ(d.actions[1].within_s, 15.0);
}

TEST(DrillConfigTest, RefusesBadVehicleReachesAndDigestMarks) {
  const std::string reaches = "[[action]]\ndo = \"vehicle_reaches\"\nowner = \"node-1\"\n";
  EXPECT_NE(ErrorOf(kHead + reaches).find("needs at least one of x_min_m"), std::string::npos);
  EXPECT_NE(ErrorOf(kHead + reaches + "x_min_m = 5\nx_max_m = 5\n")
                .find("x_max_m 5 is not above x_min_m 5"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + reaches + "z_min_m = 9\nz_max_m = 1\n")
                .find("z_max_m 1 is not above z_min_m 9"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + reaches + "x_min_m = 5\nvehicle = -1\n").find("vehicle"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + reaches + "x_min_m = 5\ntargets = \"node-2\"\n").find("no targets"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"vehicle_reaches\"\nx_min_m = 5\n").find("owner"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"digest\"\n").find("mark"), std::string::npos);
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"digest\"\nmark = \"m\"\ntargets = \"s\"\n")
                .find("no targets"),
            std::string::npos);
}

TEST(DrillConfigTest, ACommandNamesTheIdAnEarlierOneKept) {
  const DrillConfig d = ParseDrillConfig(
      kHead +
          "[[action]]\nat_s = 4\ndo = \"command\"\ntargets = \"node-1\"\n"
          "line = \"breach {ditch} 25 10\"\n"
          "[[action]]\nat_s = 1\ndo = \"command\"\ntargets = \"node-1\"\n"
          "line = \"ditch side_run_m=1.5 50,10,2.5,7 50,45,2.5,7\"\nas = \"ditch\"\n",
      "d.toml", "/base");
  ASSERT_EQ(d.actions.size(), 2u);
  EXPECT_EQ(d.actions[0].as, "ditch");  // in time order: the create first
  EXPECT_EQ(NamesUsed(d.actions[1].line), std::vector<std::string>{"ditch"});
  EXPECT_EQ(WithNames(d.actions[1].line, {{"ditch", "1:1:257"}}), "breach 1:1:257 25 10");
  EXPECT_EQ(WithNames("update {a} height_m={b}", {{"a", "1:2:3"}}), "update 1:2:3 height_m={b}");
  EXPECT_EQ(WithNames("no names", {{"a", "x"}}), "no names");
  // A name used before (in time) the command that keeps it, or never kept, or kept twice.
  const std::string use = "[[action]]\nat_s = 1\ndo = \"command\"\nline = \"destroy {x}\"\n";
  const std::string keep =
      "[[action]]\nat_s = 2\ndo = \"command\"\nline = \"crater 5 5 2\"\nas = \"x\"\n";
  EXPECT_NE(ErrorOf(kHead + use + keep).find("{x} is kept by no earlier command"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kHead + use).find("action 1"), std::string::npos);
  EXPECT_NE(ErrorOf(kHead + keep + keep).find("as = \"x\" is kept by an earlier command already"),
            std::string::npos);
  // The run directory is always known, and no command may keep an ID under its name.
  EXPECT_EQ(ErrorOf(kHead + "[[action]]\ndo = \"command\"\nline = \"render {run_dir}/a.png\"\n"),
            "");
  EXPECT_NE(ErrorOf(kHead + "[[action]]\ndo = \"command\"\nline = \"crater 5 5 2\"\n"
                            "as = \"run_dir\"\n")
                .find("run_dir is the run directory"),
            std::string::npos);
}

TEST(DrillConfigTest, ShippedDrillsParseAndNameRealProcesses) {
  const std::filesystem::path dir = std::filesystem::path(DT_SOURCE_DIR) / "configs/drills";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".toml") continue;
    ++count;
    const DrillConfig d = LoadDrillConfig(entry.path());
    const ExerciseConfig e = LoadExerciseConfig(d.exercise);
    for (const DrillAction& a : d.actions) {
      for (const std::string& n : a.targets) EXPECT_NE(e.FindProcess(n), nullptr) << a.where;
      for (const std::string& n : a.from) EXPECT_NE(e.FindProcess(n), nullptr) << a.where;
      if (!a.owner.empty()) {
        EXPECT_NE(e.FindProcess(a.owner), nullptr) << a.where;
      }
    }
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace dt
