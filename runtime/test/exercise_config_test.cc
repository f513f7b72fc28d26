#include "runtime/exercise_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include <fmt/format.h>

#include "runtime/process_runtime.h"
#include "runtime/test/exercise_config_samples.h"
#include "runtime/toml_reader.h"
#include "terrain/height_grid.h"
#include "terrain/material.h"

namespace dt {
namespace {

using test::ErrorOf;
using test::kGood;
using test::Replace;

TEST(ExerciseConfigTest, ReadsEveryField) {
  const ExerciseConfig c = ParseExerciseConfig(kGood, "ex.toml", "/base");
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.exercise_id, 7);
  EXPECT_EQ(c.run_dir, std::filesystem::path("/tmp/dt-run-t"));
  EXPECT_EQ(c.tick_hz, 20);
  EXPECT_EQ(c.terrain.posts_x, 65);
  EXPECT_EQ(c.terrain.posts_z, 65);
  EXPECT_DOUBLE_EQ(c.terrain_size_x_m(), 64 * 5.0);
  EXPECT_DOUBLE_EQ(c.terrain_size_z_m(), 64 * 5.0);
  EXPECT_EQ(c.terrain.seed, 9u);
  EXPECT_EQ(c.protocol.max_feature_period_ms, 300);
  EXPECT_EQ(c.protocol.silence_ms, 1500);
  EXPECT_EQ(c.protocol.playback_window, 256);       // default
  EXPECT_EQ(c.protocol.playback_window_max, 8192);  // default
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
  EXPECT_EQ(c.nodes[0].vehicles[0].model, VehicleModel::kPhysical);  // the default
  EXPECT_TRUE(c.friction_file.empty());                              // the built-in table
  ASSERT_NE(c.friction, nullptr);
  EXPECT_EQ(c.friction->ClassOf("jeep"), "wheeled");
  EXPECT_EQ(c.Processes().size(), 3u);
  EXPECT_EQ(c.FindProcess("node-2")->address, (NodeAddress{1, 2}));
  EXPECT_EQ(c.FindProcess("nobody"), nullptr);
  EXPECT_EQ(c.SocketPath("node-1"), std::filesystem::path("/tmp/dt-run-t/node-1.sock"));
}

TEST(ExerciseConfigTest, AVehicleNamesItsModelAndTheExerciseItsFrictionFile) {
  const ExerciseConfig light =
      ParseExerciseConfig(Replace(kGood, "heading_deg = 90", "heading_deg = 90\nmodel = \"light\""),
                          "ex.toml", "/base");
  EXPECT_EQ(light.nodes[0].vehicles[0].model, VehicleModel::kLight);

  std::string e = ErrorOf(Replace(kGood, "heading_deg = 90", "heading_deg = 90\nmodel = \"fast\""));
  EXPECT_NE(e.find("node[0].vehicle[0].model"), std::string::npos) << e;
  EXPECT_NE(e.find("fast"), std::string::npos) << e;
  EXPECT_NE(e.find("\"physical\" or \"light\""), std::string::npos) << e;

  // The shipped table named as a file gives the built-in table's coefficients.
  const std::string shipped = std::string(DT_SOURCE_DIR) + "/configs/friction.toml";
  const ExerciseConfig named = ParseExerciseConfig(
      Replace(kGood, "tick_hz = 20", "tick_hz = 20\nfriction_file = \"" + shipped + "\""),
      "ex.toml", "/base");
  EXPECT_EQ(named.friction_file, std::filesystem::path(shipped).lexically_normal());
  const ExerciseConfig built_in = ParseExerciseConfig(kGood, "ex.toml", "/base");
  for (Material m : {Material::kGrass, Material::kMud, Material::kAsphalt}) {
    EXPECT_EQ(named.friction->Lookup(m, "tracked"), built_in.friction->Lookup(m, "tracked"));
    EXPECT_EQ(named.friction->Lookup(m, "wheeled"), built_in.friction->Lookup(m, "wheeled"));
  }

  e = ErrorOf(Replace(kGood, "tick_hz = 20", "tick_hz = 20\nfriction_file = \"none.toml\""));
  EXPECT_NE(e.find("exercise.friction_file"), std::string::npos) << e;
  EXPECT_NE(e.find("/base/none.toml"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, VehiclesTableSetsTheDeadReckoningThresholds) {
  const ExerciseConfig defaults = ParseExerciseConfig(kGood, "ex.toml", "/base");
  EXPECT_EQ(defaults.dead_reckoning.position_m, 1.0);
  EXPECT_EQ(defaults.dead_reckoning.heartbeat_s, 5.0);
  EXPECT_EQ(defaults.dead_reckoning.algorithm, DeadReckoningAlgorithm::kRvw);
  const std::string with = std::string(kGood) +
                           "\n[vehicles]\nposition_threshold_m = 0.5\n"
                           "orientation_threshold_deg = 2\nheartbeat_s = 10\n"
                           "timeout_heartbeats = 3\ndead_reckoning = \"fpw\"\n";
  const ExerciseConfig c = ParseExerciseConfig(with, "ex.toml", "/base");
  EXPECT_EQ(c.dead_reckoning.position_m, 0.5);
  EXPECT_EQ(c.dead_reckoning.orientation_deg, 2.0);
  EXPECT_EQ(c.dead_reckoning.timeout_s(), 30.0);
  EXPECT_EQ(c.dead_reckoning.algorithm, DeadReckoningAlgorithm::kFpw);
  std::string e = ErrorOf(std::string(kGood) + "\n[vehicles]\nheartbeat_s = 0\n");
  EXPECT_NE(e.find("vehicles.heartbeat_s"), std::string::npos) << e;
  e = ErrorOf(std::string(kGood) + "\n[vehicles]\ndead_reckoning = \"dvw\"\n");
  EXPECT_NE(e.find("vehicles.dead_reckoning"), std::string::npos) << e;
  EXPECT_NE(e.find("static, fpw"), std::string::npos) << e;
}

// Groups of node-2 (the terrain is 320 m a side).
std::string WithGroup(const std::string& group) {
  return std::string(kGood) + "[[node.group]]\n" + group;
}

TEST(ExerciseConfigTest, AGroupReadsItsFieldsAndDefaultsToPhysicalVehiclesOverTheWholeTerrain) {
  const ExerciseConfig c = ParseExerciseConfig(
      WithGroup("type = \"tank\"\ncount = 30\nseed = 5\nmodel = \"light\"\n"
                "area = { x_min_m = 10, x_max_m = 200, z_min_m = 20.5, z_max_m = 300 }\n"
                "[[node.group]]\ncount = 7\n"),
      "ex.toml", "/base");
  ASSERT_EQ(c.nodes[1].groups.size(), 2u);
  const VehicleGroupConfig& g = c.nodes[1].groups[0];
  EXPECT_EQ(g.type, "tank");
  EXPECT_EQ(g.count, 30);
  EXPECT_EQ(g.seed, 5u);
  EXPECT_EQ(g.model, VehicleModel::kLight);
  EXPECT_EQ(g.area.x_min_m, 10.0);
  EXPECT_EQ(g.area.x_max_m, 200.0);
  EXPECT_EQ(g.area.z_min_m, 20.5);
  EXPECT_EQ(g.area.z_max_m, 300.0);
  const VehicleGroupConfig& d = c.nodes[1].groups[1];
  EXPECT_EQ(d.type, "truck");
  EXPECT_EQ(d.model, VehicleModel::kPhysical);
  EXPECT_EQ(d.seed, 1u);
  EXPECT_EQ(d.area.x_min_m, 0.0);
  EXPECT_EQ(d.area.x_max_m, 320.0);
  EXPECT_EQ(d.area.z_max_m, 320.0);
  EXPECT_EQ(c.nodes[1].start_vehicle_count(), 37);
  EXPECT_EQ(c.nodes[0].start_vehicle_count(), 1);
  EXPECT_TRUE(c.nodes[0].groups.empty());
}

TEST(ExerciseConfigTest, AGroupsErrorsNameTheField) {
  struct Case {
    const char* group;
    const char* names;  // in the message
  };
  const Case cases[] = {
      {"count = 0\n", "node[1].group[0].count"},
      {"count = 10001\n", "node[1].group[0].count"},
      {"count = 2.5\n", "node[1].group[0].count"},
      {"type = \"tank\"\n", "node[1].group[0].count: missing"},
      {"count = 3\n"
       "type = \"horse\"\n",
       "node[1].group[0].type"},
      {"count = 3\n"
       "model = \"heavy\"\n",
       "node[1].group[0].model"},
      {"count = 3\n"
       "seed = -1\n",
       "node[1].group[0].seed"},
      {"count = 3\ncuont = 3\n", "node[1].group[0].cuont: unknown key (did you mean \"count\"?)"},
      {"count = 3\n"
       "area = { x_min_m = 0, x_max_m = 321 }\n",
       "node[1].group[0].area.x_max_m"},
      {"count = 3\n"
       "area = { z_min_m = -5 }\n",
       "node[1].group[0].area.z_min_m"},
      {"count = 3\n"
       "area = { x_min_m = 100, x_max_m = 50 }\n",
       "node[1].group[0].area.x_max_m"},
      {"count = 3\n"
       "area = { z_min_m = 100, z_max_m = 110 }\n",
       "node[1].group[0].area.z_max_m"},
      {"count = 3\n"
       "area = { x_min = 1 }\n",
       "node[1].group[0].area.x_min: unknown key"},
      {"count = 10000\n[[node.group]]\ncount = 10000\n[[node.group]]\ncount = 10000\n"
       "[[node.group]]\ncount = 10000\n[[node.group]]\ncount = 10000\n[[node.group]]\n"
       "count = 10000\n[[node.group]]\ncount = 1\n",
       "hold 60001 vehicles, more than 60000"},
  };
  for (const Case& k : cases) {
    const std::string e = ErrorOf(WithGroup(k.group));
    EXPECT_NE(e.find(k.names), std::string::npos) << k.group << " gave: " << e;
  }
  // A group on the server is an unknown key, not ignored.
  const std::string e =
      ErrorOf(Replace(kGood, "host = 100\n", "host = 100\n[[server.group]]\ncount = 1\n"));
  EXPECT_NE(e.find("server.group"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, ReadsDelaysWithJitterAndTheHostsTable) {
  const ExerciseConfig c = ParseExerciseConfig(
      Replace(kGood, "seed = 4\n",
              "seed = 4\ndelay_ms = 20\njitter_ms = 5\nother_site_delay_ms = 50\n"
              "other_site_jitter_ms = 10\n[hosts]\nmode = \"wan\"\nrate_mbit = 10\n"),
      "ex.toml", "/base");
  EXPECT_EQ(c.faults.min_delay, 15);
  EXPECT_EQ(c.faults.max_delay, 25);
  EXPECT_EQ(c.faults.other_site_min_delay, 40);
  EXPECT_EQ(c.faults.other_site_max_delay, 60);
  EXPECT_EQ(c.hosts.mode, HostsMode::kWan);
  EXPECT_DOUBLE_EQ(c.hosts.rate_mbit, 10.0);
  EXPECT_EQ(c.hosts.queue_ms, 50);  // default
  EXPECT_EQ(ParseExerciseConfig(kGood, "ex.toml", "/base").hosts.mode, HostsMode::kNone);

  std::string e = ErrorOf(Replace(kGood, "seed = 4\n", "seed = 4\ndelay_ms = 5\njitter_ms = 6\n"));
  EXPECT_NE(e.find("faults.jitter_ms"), std::string::npos) << e;
  EXPECT_NE(e.find("delay_ms = 5"), std::string::npos) << e;
  e = ErrorOf(Replace(kGood, "seed = 4\n", "seed = 4\n[hosts]\nmode = \"cloud\"\n"));
  EXPECT_NE(e.find("hosts.mode"), std::string::npos) << e;
  EXPECT_NE(e.find("cloud"), std::string::npos) << e;
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

  // A request longer than a Playback PDU may span (65 536) is refused at load.
  e = ErrorOf(
      Replace(kGood, "silence_ms = 1500", "silence_ms = 1500\nplayback_window_max = 70000"));
  EXPECT_NE(e.find("protocol.playback_window_max"), std::string::npos) << e;
  EXPECT_NE(e.find("70000"), std::string::npos) << e;
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

TEST(ExerciseConfigTest, AMistypedKeyIsNamedBeforeTheKeyItLeavesMissing) {
  // "hots" for "host": the typo is reported with the key meant, not as "host: missing".
  std::string e = ErrorOf(Replace(kGood, "host = 2", "hots = 2"));
  EXPECT_NE(e.find("ex.toml: node[1].hots: unknown key (did you mean \"host\"?) (value 2)"),
            std::string::npos)
      << e;
  e = ErrorOf(Replace(kGood, "[server]", "[srever]"));
  EXPECT_NE(e.find("ex.toml: srever: unknown key (did you mean \"server\"?)"), std::string::npos)
      << e;
  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "post_per_side = 65"));
  EXPECT_NE(e.find("terrain.post_per_side: unknown key (did you mean \"posts_per_side\"?)"),
            std::string::npos)
      << e;
  // Far from every key the table may hold: named without a guess.
  e = ErrorOf(Replace(kGood, "host = 2", "address = 2"));
  EXPECT_NE(e.find("ex.toml: node[1].address: unknown key (value 2)"), std::string::npos) << e;
  // A key of another table is unknown here, though it is known there.
  e = ErrorOf(Replace(kGood, "host = 100", "host = 100\nscenario = \"s.toml\""));
  EXPECT_NE(e.find("ex.toml: server.scenario: unknown key"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, NearestKeySuggestsOnlyLikelyTypos) {
  const std::vector<std::string> keys = {"name", "site", "host", "scenario", "vehicle"};
  EXPECT_EQ(NearestKey("hots", keys), "host");           // two letters swapped
  EXPECT_EQ(NearestKey("scenarios", keys), "scenario");  // one letter added
  EXPECT_EQ(NearestKey("vehcle", keys), "vehicle");      // one letter dropped
  EXPECT_EQ(NearestKey("address", keys), std::nullopt);
  EXPECT_EQ(NearestKey("host", keys), std::nullopt);  // the key itself is no suggestion
  EXPECT_EQ(NearestKey("ab", {"id"}), std::nullopt);  // as many edits as letters
}

TEST(ExerciseConfigTest, AGridTooLargeForMemoryIsRefusedNamingTheKey) {
  const std::string e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_per_side = 65536"));
  EXPECT_NE(e.find(fmt::format("ex.toml: terrain.posts_per_side: must be in [2, {}] (value 65536)",
                               kMaxPostsPerSide)),
            std::string::npos)
      << e;
  EXPECT_EQ(ErrorOf(Replace(kGood, "posts_per_side = 65",
                            fmt::format("posts_per_side = {}", kMaxPostsPerSide))),
            "");
}

// A rectangular ground: posts_x and posts_z, both or neither, never with posts_per_side.
TEST(ExerciseConfigTest, ARectangularGroundTakesPostsXAndPostsZ) {
  const std::string rect =
      Replace(kGood, "posts_per_side = 65", "posts_x = 65\nposts_z = 17");  // 320 m x 80 m
  const ExerciseConfig c = ParseExerciseConfig(rect, "ex.toml", "/base");
  EXPECT_EQ(c.terrain.posts_x, 65);
  EXPECT_EQ(c.terrain.posts_z, 17);
  EXPECT_DOUBLE_EQ(c.terrain_size_x_m(), 320.0);
  EXPECT_DOUBLE_EQ(c.terrain_size_z_m(), 80.0);
  const HeightGrid ground = MakeRandomTerrain(c.terrain);
  EXPECT_EQ(ground.posts_x(), 65);
  EXPECT_EQ(ground.posts_z(), 17);

  // A vehicle is bounded per axis: x 300 m is on, z 100 m is off, named by its key.
  std::string e = ErrorOf(Replace(rect, "x_m = 10", "x_m = 300"));
  EXPECT_EQ(e, "");
  e = ErrorOf(Replace(rect, "z_m = 20.5", "z_m = 100"));
  EXPECT_NE(e.find("node[0].vehicle[0].z_m: vehicle at (10, 100) is off the 320 x 80 m terrain"),
            std::string::npos)
      << e;
  // A group's area is bounded per axis too, and defaults to the whole rectangle.
  const ExerciseConfig g = ParseExerciseConfig(
      rect + "[[node.group]]\ncount = 2\n[[node.group]]\ncount = 1\narea = { z_max_m = 80 }\n",
      "ex.toml", "/base");
  EXPECT_EQ(g.nodes[1].groups[0].area.x_max_m, 320.0);
  EXPECT_EQ(g.nodes[1].groups[0].area.z_max_m, 80.0);
  e = ErrorOf(rect + "[[node.group]]\ncount = 1\narea = { z_max_m = 81 }\n");
  EXPECT_NE(e.find("area.z_max_m: must be in [0, 80]"), std::string::npos) << e;

  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_x = 65"));
  EXPECT_NE(e.find("ex.toml: terrain.posts_x: posts_x needs posts_z too"), std::string::npos) << e;
  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_z = 65"));
  EXPECT_NE(e.find("ex.toml: terrain.posts_z: posts_z needs posts_x too"), std::string::npos) << e;
  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_per_side = 65\nposts_x = 9"));
  EXPECT_NE(e.find("ex.toml: terrain.posts_per_side: give either posts_per_side (a square grid) or "
                   "posts_x and posts_z, not both"),
            std::string::npos)
      << e;
  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_x = 65\nposts_z = 4098"));
  EXPECT_NE(e.find("ex.toml: terrain.posts_z: must be in [2, 4097] (value 4098)"),
            std::string::npos)
      << e;
  e = ErrorOf(Replace(kGood, "posts_per_side = 65", "posts_x = 1\nposts_z = 9"));
  EXPECT_NE(e.find("ex.toml: terrain.posts_x: must be in [2, 4097] (value 1)"), std::string::npos)
      << e;
}

TEST(ExerciseConfigTest, NeedsServerAndANode) {
  std::string no_nodes = kGood;
  no_nodes = no_nodes.substr(0, no_nodes.find("[[node]]"));
  EXPECT_NE(ErrorOf(no_nodes).find("at least one [[node]]"), std::string::npos);
  std::string no_server = Replace(kGood, "[server]\nname = \"server\"\nsite = 1\nhost = 100\n", "");
  EXPECT_NE(ErrorOf(no_server).find("server: missing"), std::string::npos) << ErrorOf(no_server);
}

TEST(ExerciseConfigTest, AnExerciseWithoutAServerSaysSo) {
  const std::string server_table = "[server]\nname = \"server\"\nsite = 1\nhost = 100\n";
  const std::string serverless = Replace(Replace(kGood, server_table, ""), "silence_ms = 1500",
                                         "silence_ms = 1500\nrequire_server = false");
  const ExerciseConfig c = ParseExerciseConfig(serverless, "ex.toml", "/base");
  EXPECT_FALSE(c.server.has_value());
  EXPECT_FALSE(c.require_server());
  ASSERT_EQ(c.Processes().size(), 2u);
  EXPECT_EQ(c.Processes()[0]->name, "node-1");
  EXPECT_EQ(c.FindProcess("server"), nullptr);

  const ExerciseConfig with = ParseExerciseConfig(kGood, "ex.toml", "/base");
  ASSERT_TRUE(with.server.has_value());
  EXPECT_TRUE(with.require_server());
  EXPECT_EQ(with.server->address, (NodeAddress{1, 100}));

  // A server, or a standby, in an exercise that says it has none is a contradiction.
  std::string e = ErrorOf(serverless + server_table);
  EXPECT_NE(e.find("ex.toml: server: an exercise with [protocol] require_server = false"),
            std::string::npos)
      << e;
  e = ErrorOf(serverless + "[standby]\nname = \"standby\"\nsite = 1\nhost = 101\n");
  EXPECT_NE(e.find("standby: an exercise with"), std::string::npos) << e;
  // require_server = true is the default, and it needs its [server].
  e = ErrorOf(Replace(serverless, "require_server = false", "require_server = true"));
  EXPECT_NE(e.find("server: missing"), std::string::npos) << e;
  EXPECT_NE(e.find("require_server = false for one without"), std::string::npos) << e;
  e = ErrorOf(Replace(serverless, "require_server = false", "require_server = 0"));
  EXPECT_NE(e.find("protocol.require_server"), std::string::npos) << e;
}

TEST(ExerciseConfigTest, LoadResolvesScenarioBesideTheFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dt-excfg-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "e.toml") << kGood; }
  const ExerciseConfig c = LoadExerciseConfig(dir / "e.toml");
  EXPECT_EQ(c.nodes[0].scenario, dir / "scen/a.toml");
  // A bare file name: its folder is the current directory.
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  std::string bare_error;
  std::filesystem::path bare_scenario;
  try {
    bare_scenario = LoadExerciseConfig("e.toml").nodes[0].scenario;
  } catch (const std::exception& e) {
    bare_error = e.what();
  }
  std::filesystem::current_path(cwd);
  EXPECT_EQ(bare_error, "");
  EXPECT_EQ(bare_scenario, std::filesystem::canonical(dir) / "scen/a.toml");
  std::filesystem::remove_all(dir);
  EXPECT_THROW(LoadExerciseConfig(dir / "missing.toml"), std::invalid_argument);
}

TEST(ExerciseConfigTest, ShippedDemoParses) {
  const ExerciseConfig c =
      LoadExerciseConfig(std::filesystem::path(DT_SOURCE_DIR) / "configs/exercises/demo.toml");
  EXPECT_EQ(c.nodes.size(), 3u);
  ASSERT_EQ(c.nodes[1].groups.size(), 1u);
  EXPECT_EQ(c.nodes[1].start_vehicle_count(), 21);
  EXPECT_FALSE(c.auth.keyless);
  EXPECT_EQ(c.auth.key_file.filename(), "demo.key");
  // Its ground is the committed GeoTIFF (docs/real-ground.md), near 36.6 N 121.9 W.
  ASSERT_TRUE(c.elevation.has_value());
  EXPECT_EQ(c.terrain.posts_x, 129);
  EXPECT_EQ(c.terrain.posts_z, 129);
  EXPECT_DOUBLE_EQ(c.terrain.spacing_m, 10.0);
  ASSERT_TRUE(c.dis.has_value());
  EXPECT_NEAR(c.dis->latitude_deg, 36.6, 1e-4);
  EXPECT_NEAR(c.dis->longitude_deg, -121.9, 1e-4);
  for (const ProcessConfig& n : c.nodes) {
    if (!n.scenario.empty()) {
      EXPECT_TRUE(std::filesystem::exists(n.scenario)) << n.scenario;
    }
  }
}

}  // namespace
}  // namespace dt

namespace dt {
namespace {

// The live view (docs/view.md): [view] is optional, names an observer member and where its page
// is served; its name and address must be unique like every process's.
TEST(ExerciseConfigTest, AViewIsAnObserverMemberWithItsPageAddress) {
  const std::string with_view =
      std::string(kGood) + "\n[view]\nname = \"view\"\nsite = 1\nhost = 50\nhttp_port = 9000\n";
  ExerciseConfig c = ParseExerciseConfig(with_view, "ex.toml", "/base");
  ASSERT_TRUE(c.view.has_value());
  EXPECT_EQ(c.view->process.name, "view");
  EXPECT_EQ(c.view->http_address, "127.0.0.1");  // this host only unless the file says so
  EXPECT_EQ(c.view->http_port, 9000);
  EXPECT_EQ(c.FindProcess("view"), &c.view->process);
  for (const ProcessConfig* p : c.Processes()) EXPECT_NE(p->name, "view");  // not a replica peer
  const ReplicaConfig rc = MakeReplicaConfig(c, *c.FindProcess("node-1"), NodeRole::kNode);
  EXPECT_EQ(rc.members.at(NodeAddress{1, 50}), NodeRole::kObserver);
  EXPECT_FALSE(ParseExerciseConfig(kGood, "ex.toml", "/base").view.has_value());

  std::string e = ErrorOf(Replace(with_view, "host = 50", "host = 100"));
  EXPECT_NE(e.find("address 1:100"), std::string::npos) << e;
  e = ErrorOf(Replace(with_view, "http_port = 9000", "http_port = 70000"));
  EXPECT_NE(e.find("view.http_port"), std::string::npos) << e;
}

// The DIS gateway (docs/dis.md "The gateway"): [dis] is optional; an observer member unless it
// imports craters, then a node member; its UDP settings and geodetic origin are checked, the
// error naming the key.
TEST(ExerciseConfigTest, ADisGatewayIsAMemberWithItsUdpSettingsAndOrigin) {
  const std::string with_dis = std::string(kGood) +
                               "\n[dis]\nname = \"dis\"\nsite = 1\nhost = 60\n"
                               "latitude_deg = 36.6\nlongitude_deg = -121.9\nheight_m = 20\n";
  ExerciseConfig c = ParseExerciseConfig(with_dis, "ex.toml", "/base");
  ASSERT_TRUE(c.dis.has_value());
  EXPECT_EQ(c.dis->udp_port, 3000);
  EXPECT_EQ(c.dis->destination, "127.255.255.255");  // this host's broadcast unless told
  EXPECT_FALSE(c.dis->multicast());
  EXPECT_EQ(c.dis->dis_exercise_id, 1);
  EXPECT_FALSE(c.dis->import_craters);
  EXPECT_EQ(c.dis->bundle_max_bytes, 0);  // one PDU per datagram unless told
  EXPECT_DOUBLE_EQ(c.dis->latitude_deg, 36.6);
  EXPECT_DOUBLE_EQ(c.dis->longitude_deg, -121.9);
  EXPECT_EQ(c.FindProcess("dis"), &c.dis->process);
  ReplicaConfig rc = MakeReplicaConfig(c, *c.FindProcess("node-1"), NodeRole::kNode);
  EXPECT_EQ(rc.members.at(NodeAddress{1, 60}), NodeRole::kObserver);
  c = ParseExerciseConfig(with_dis +
                              "import_craters = true\ndestination = \"239.1.2.3\"\n"
                              "bundle_max_bytes = 1400\n",
                          "ex.toml", "/base");
  EXPECT_TRUE(c.dis->multicast());
  EXPECT_EQ(c.dis->bundle_max_bytes, 1400);
  rc = MakeReplicaConfig(c, *c.FindProcess("node-1"), NodeRole::kNode);
  EXPECT_EQ(rc.members.at(NodeAddress{1, 60}), NodeRole::kNode);

  for (const auto& [bad, key] : std::vector<std::pair<std::string, std::string>>{
           {"latitude_deg = 91", "dis.latitude_deg"},
           {"longitude_deg = -181", "dis.longitude_deg"},
           {"height_m = nan", "dis.height_m"},
           {"udp_port = 0", "dis.udp_port"},
           {"destination = \"bogus\"", "dis.destination"},
           {"dis_exercise_id = 0", "dis.dis_exercise_id"},
           {"import_craters = 3", "dis.import_craters"},
           {"bundle_max_bytes = 100", "dis.bundle_max_bytes"},
           {"bundle_max_bytes = 70000", "dis.bundle_max_bytes"},
           {"udp_prot = 3000", "dis.udp_prot"}}) {
    const std::string k = bad.substr(0, bad.find(' '));
    const size_t at = with_dis.find("\n" + k + " = ");
    const std::string text =
        at == std::string::npos
            ? with_dis + bad + "\n"
            : with_dis.substr(0, at + 1) + bad + with_dis.substr(with_dis.find('\n', at + 1));
    const std::string e = ErrorOf(text);
    EXPECT_NE(e.find(key), std::string::npos) << bad << ": " << e;
  }
  const std::string e = ErrorOf(Replace(with_dis, "host = 60", "host = 100"));
  EXPECT_NE(e.find("address 1:100"), std::string::npos) << e;
}

}  // namespace
}  // namespace dt
