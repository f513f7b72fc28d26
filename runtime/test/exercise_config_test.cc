#include "runtime/exercise_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace dt {
namespace {

const char* kGood = R"(
[exercise]
name = "t"
id = 7
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "/tmp/dt-run-t"
tick_hz = 20

[terrain]
posts_per_side = 65
spacing_m = 5.0
relief_m = 20
seed = 9

[protocol]
max_feature_period_ms = 300
silence_ms = 1500
anti_entropy_period_ms = 1500

[faults]
drop_probability = 0.3
seed = 4

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1
scenario = "scen/a.toml"
[[node.vehicle]]
type = "jeep"
x_m = 10
z_m = 20.5
heading_deg = 90

[[node]]
name = "node-2"
site = 1
host = 2
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The message of the std::invalid_argument thrown for `text`, or "" if it parses.
std::string ErrorOf(const std::string& text) {
  try {
    ParseExerciseConfig(text, "ex.toml", "/base");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ExerciseConfigTest, ReadsEveryField) {
  const ExerciseConfig c = ParseExerciseConfig(kGood, "ex.toml", "/base");
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.exercise_id, 7);
  EXPECT_EQ(c.run_dir, std::filesystem::path("/tmp/dt-run-t"));
  EXPECT_EQ(c.tick_hz, 20);
  EXPECT_EQ(c.terrain.posts_per_side, 65);
  EXPECT_DOUBLE_EQ(c.terrain_size_m(), 64 * 5.0);
  EXPECT_EQ(c.terrain.seed, 9u);
  EXPECT_EQ(c.protocol.max_feature_period_ms, 300);
  EXPECT_EQ(c.protocol.silence_ms, 1500);
  EXPECT_EQ(c.protocol.playback_window, 256);  // default
  EXPECT_EQ(c.protocol.anti_entropy_period_ms, 1500);
  EXPECT_DOUBLE_EQ(c.faults.drop_probability, 0.3);
  EXPECT_EQ(c.fault_seed, 4u);
  EXPECT_FALSE(c.standby.has_value());
  ASSERT_EQ(c.nodes.size(), 2u);
  EXPECT_EQ(c.nodes[0].scenario, std::filesystem::path("/base/scen/a.toml"));
  EXPECT_TRUE(c.nodes[1].scenario.empty());
  ASSERT_EQ(c.nodes[0].vehicles.size(), 1u);
  EXPECT_EQ(c.nodes[0].vehicles[0].type, "jeep");
  EXPECT_DOUBLE_EQ(c.nodes[0].vehicles[0].z_m, 20.5);
  EXPECT_NEAR(c.nodes[0].vehicles[0].heading_rad, std::numbers::pi / 2, 1e-12);
  EXPECT_EQ(c.Processes().size(), 3u);
  EXPECT_EQ(c.FindProcess("node-2")->address, (NodeAddress{1, 2}));
  EXPECT_EQ(c.FindProcess("nobody"), nullptr);
  EXPECT_EQ(c.SocketPath("node-1"), std::filesystem::path("/tmp/dt-run-t/node-1.sock"));
}

TEST(ExerciseConfigTest, ErrorsNameFileKeyAndValue) {
  std::string e = ErrorOf(Replace(kGood, "tick_hz = 20", "tick_hz = 0"));
  EXPECT_NE(e.find("ex.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("exercise.tick_hz"), std::string::npos) << e;
  EXPECT_NE(e.find("value 0"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "drop_probability = 0.3", "drop_probability = 1.5"));
  EXPECT_NE(e.find("faults.drop_probability"), std::string::npos) << e;
  EXPECT_NE(e.find("1.5"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "type = \"jeep\"", "type = \"horse\""));
  EXPECT_NE(e.find("node[0].vehicle[0].type"), std::string::npos) << e;
  EXPECT_NE(e.find("horse"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "spacing_m = 5.0", "spacing_m = \"five\""));
  EXPECT_NE(e.find("terrain.spacing_m"), std::string::npos) << e;
  EXPECT_NE(e.find("five"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, RefusesUnknownKeysTyposAndDuplicates) {
  std::string e = ErrorOf(Replace(kGood, "tick_hz = 20", "tick_hz = 20\ntickhz = 3"));
  EXPECT_NE(e.find("exercise.tickhz: unknown key"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "host = 2", "host = 1"));
  EXPECT_NE(e.find("1:1"), std::string::npos) << e;
  EXPECT_NE(e.find("twice"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "name = \"node-2\"", "name = \"node-1\""));
  EXPECT_NE(e.find("\"node-1\" is used twice"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "silence_ms = 1500", "silence_ms = 200"));
  EXPECT_NE(e.find("protocol.silence_ms"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "x_m = 10", "x_m = 1000"));
  EXPECT_NE(e.find("off the 320 m terrain"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "transport = \"udpm", "transport = \"tcp"));
  EXPECT_NE(e.find("exercise.transport"), std::string::npos) << e;

  e = ErrorOf("[exercise\nname=1");
  EXPECT_NE(e.find("ex.toml:1"), std::string::npos) << e;
  EXPECT_NE(e.find("syntax"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, NeedsServerAndANode) {
  std::string no_nodes = kGood;
  no_nodes = no_nodes.substr(0, no_nodes.find("[[node]]"));
  EXPECT_NE(ErrorOf(no_nodes).find("at least one [[node]]"), std::string::npos);
  std::string no_server = Replace(kGood, "[server]\nname = \"server\"\nsite = 1\nhost = 100\n", "");
  EXPECT_NE(ErrorOf(no_server).find("server: missing"), std::string::npos) << ErrorOf(no_server);
}

TEST(ExerciseConfigTest, LoadResolvesScenarioBesideTheFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dt-excfg-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "e.toml") << kGood; }
  const ExerciseConfig c = LoadExerciseConfig(dir / "e.toml");
  EXPECT_EQ(c.nodes[0].scenario, dir / "scen/a.toml");
  std::filesystem::remove_all(dir);
  EXPECT_THROW(LoadExerciseConfig(dir / "missing.toml"), std::invalid_argument);
}

TEST(ExerciseConfigTest, ShippedDemoParses) {
  const ExerciseConfig c =
      LoadExerciseConfig(std::filesystem::path(DT_SOURCE_DIR) / "configs/exercises/demo.toml");
  EXPECT_EQ(c.nodes.size(), 3u);
  for (const ProcessConfig& n : c.nodes) {
    if (!n.scenario.empty()) {
      EXPECT_TRUE(std::filesystem::exists(n.scenario)) << n.scenario;
    }
  }
}

}  // namespace
}  // namespace dt
