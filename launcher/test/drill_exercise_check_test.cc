#include "launcher/drill_exercise_check.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace dt {
namespace {

const std::string kExercise =
    "[exercise]\nname = \"e\"\nrun_dir = \"/tmp/unused\"\n[auth]\nmode = \"none\"\n[terrain]\n"
    "[server]\nname = \"server\"\nsite = 1\nhost = 100\n"
    "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
    "[[node]]\nname = \"node-2\"\nsite = 1\nhost = 2\n";

// The message CheckDrillAgainstExercise refuses the drill's actions with; "" if it accepts them.
std::string Refusal(const std::string& actions, const std::string& exercise = kExercise) {
  const DrillConfig d =
      ParseDrillConfig("[drill]\nname = \"x\"\nexercise = \"e.toml\"\ndeadline_s = 60\n" + actions,
                       "d.toml", "/base");
  try {
    CheckDrillAgainstExercise(d, ParseExerciseConfig(exercise, "e.toml", "/base"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DrillExerciseCheckTest, AcceptsActionsOnTheExercisesProcesses) {
  EXPECT_EQ(Refusal("[[action]]\ndo = \"kill\"\ntargets = \"node-2\"\n"
                    "[[action]]\ndo = \"partition\"\ntargets = \"server\"\nfrom = \"node-1\"\n"
                    "[[action]]\ndo = \"vehicles_seen\"\nowner = \"node-1\"\n"
                    "targets = \"node-2\"\n"
                    "[[action]]\ndo = \"chaos\"\nduration_s = 10\nmax_down = 3\n"),
            "");
}

TEST(DrillExerciseCheckTest, RefusesAnExerciseWithoutAServer) {
  EXPECT_EQ(Refusal("",
                    "[exercise]\nname = \"e\"\n[auth]\nmode = \"none\"\n[terrain]\n"
                    "[protocol]\nrequire_server = false\n"
                    "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"),
            "d.toml: e.toml has no server ([protocol] require_server = false); drills need one");
}

TEST(DrillExerciseCheckTest, RefusesNamesTheExerciseLacks) {
  EXPECT_EQ(Refusal("[[action]]\ndo = \"kill\"\ntargets = \"node-3\"\n"),
            "d.toml action 1: e.toml has no process named \"node-3\"");
  EXPECT_EQ(Refusal("[[action]]\ndo = \"heal\"\n"
                    "[[action]]\ndo = \"partition\"\ntargets = \"node-1\"\nfrom = \"standby\"\n"),
            "d.toml action 2: e.toml has no process named \"standby\"");
  // The server is a process, but vehicles are nodes'.
  EXPECT_EQ(Refusal("[[action]]\ndo = \"vehicle_reaches\"\nowner = \"server\"\nx_min_m = 1\n"),
            "d.toml action 1: e.toml has no node named \"server\" (owner)");
  EXPECT_EQ(Refusal("[[action]]\ndo = \"sample_vehicles\"\ntargets = [\"node-1\", \"server\"]\n"
                    "duration_s = 5\nmin_tilt_deg = 5\n"),
            "d.toml action 1: \"server\" is not a node (vehicle actions watch nodes)");
}

TEST(DrillExerciseCheckTest, RefusesChaosDowningMoreThanItsTargets) {
  // No targets: every process of the exercise (three).
  EXPECT_EQ(Refusal("[[action]]\ndo = \"chaos\"\nduration_s = 10\nmax_down = 4\n"),
            "d.toml action 1: chaos max_down 4 exceeds its 3 targets");
  EXPECT_EQ(Refusal("[[action]]\ndo = \"chaos\"\nduration_s = 10\nmax_down = 3\n"
                    "targets = [\"node-1\", \"node-2\"]\n"),
            "d.toml action 1: chaos max_down 3 exceeds its 2 targets");
}

}  // namespace
}  // namespace dt
