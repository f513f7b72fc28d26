// A whole node (NodeApp over an in-process memq transport, no server) driving its vehicles through
// a scenario, watched through its control commands as dt_ctl would see them: the vehicles move by
// the model the exercise file names for each.
#include "node/node_app.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "pdu/conversion.h"
#include "pdu/pdu_traits.h"
#include "pdu/validation.h"
#include "render/png_io.h"
#include "runtime/exercise_config.h"
#include "runtime/process_runtime.h"
#include "runtime/status_report.h"

namespace dt {
namespace {

// Two destroyed 6 m bridges on flat ground (ramp 1 from x 70 to 100, span to 140, ramp 2 to 170),
// one at z 100 and one at z 220, and a tank heading east onto each (8 and 12 m/s) for 25 s.
constexpr const char* kScenario = R"(
[[step]]
action = "bridge"
name = "north"
x_m = 100
z_m = 220
direction_deg = 0
width_m = 10
ramp1_m = 30
span_m = 40
ramp2_m = 30
height1_m = 6
height2_m = 6

[[step]]
action = "bridge"
name = "south"
x_m = 100
z_m = 100
direction_deg = 0
width_m = 10
ramp1_m = 30
span_m = 40
ramp2_m = 30
height1_m = 6
height2_m = 6

[[step]]
at_s = 0.5
action = "update"
target = "north"
status = 1

[[step]]
action = "update"
target = "south"
status = 1

[[step]]
at_s = 1.0
action = "drive"
vehicle = 0
speed_mps = 8
duration_s = 25

[[step]]
action = "drive"
vehicle = 1
speed_mps = 12
duration_s = 25
)";

// "vehicle <i> <type> key=value ..." lines of a status reply, by index, as key -> value.
std::map<int, std::map<std::string, std::string>> VehicleLines(const std::string& status) {
  std::map<int, std::map<std::string, std::string>> out;
  std::istringstream in(status);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string key, type;
    int index = -1;
    if (!(words >> key) || key != "vehicle" || !(words >> index >> type)) continue;
    out[index]["type"] = type;
    for (std::string kv; words >> kv;) {
      const size_t eq = kv.find('=');
      if (eq != std::string::npos) out[index][kv.substr(0, eq)] = kv.substr(eq + 1);
    }
  }
  return out;
}

class NodeAppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / fmt::format("dt-node-app-test-{}", ::getpid());
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "scenario.toml") << kScenario;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // The exercise of one node with these [[node.vehicle]] tables, playing kScenario if asked.
  ExerciseConfig Exercise(const std::string& vehicles, bool scenario = true) const {
    const std::string text = fmt::format(
        "[exercise]\nname = \"node-app\"\ntransport = \"memq://\"\nrun_dir = \"{}\"\n"
        "[auth]\nmode = \"none\"\n"
        "[terrain]\nposts_per_side = 33\nspacing_m = 10\nrelief_m = 0\n"
        "[protocol]\nrequire_server = false\nmax_feature_period_ms = 50\nsilence_ms = 200\n"
        "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n{}{}",
        dir_.string(), scenario ? "scenario = \"scenario.toml\"\n" : "", vehicles);
    return ParseExerciseConfig(text, "ex.toml", dir_);
  }

  std::filesystem::path dir_;
};

TEST_F(NodeAppTest, APhysicalTankDiesAtADestroyedBridgesDropWhereALightOneDrivesOn) {
  const ExerciseConfig exercise = Exercise(
      "[[node.vehicle]]\ntype = \"tank\"\nx_m = 50\nz_m = 100\n"
      "[[node.vehicle]]\ntype = \"tank\"\nx_m = 50\nz_m = 220\nmodel = \"light\"\n");
  NodeApp node(exercise, exercise.nodes[0]);
  ASSERT_EQ(node.vehicles().size(), 2u);
  EXPECT_EQ(node.vehicles()[0].model(), VehicleModel::kPhysical);
  EXPECT_EQ(node.vehicles()[1].model(), VehicleModel::kLight);

  // Simulated time: 30 Hz ticks, the clock advanced by the test, not read.
  constexpr int64_t kTickMs = 33;
  int64_t now_ms = 0;
  node.Start(now_ms);
  std::map<int, std::map<std::string, std::string>> seen_on_bridge;
  // Until the physical tank is dead and the light one past the bridge, for at most 30 s.
  for (int tick = 0; tick < 30 * 30; ++tick) {
    now_ms += kTickMs;
    node.Tick(now_ms, static_cast<double>(kTickMs) / 1000.0);
    node.Receive(0);
    if (node.vehicles()[0].bridge().number != 0) {
      seen_on_bridge = VehicleLines(node.Handle("status").body);
    }
    if (!node.vehicles()[0].alive() && node.vehicles()[1].pose().x_m > 180.0) break;
  }
  ASSERT_TRUE(node.ready());
  EXPECT_EQ(node.replica().live_feature_count(), 2u);

  const ControlReply status = node.Handle("status");
  ASSERT_TRUE(status.ok) << status.error;
  // A node's whole reply reads back, its own lines kept after the common ones, byte for byte.
  const Result<StatusReport> report = StatusReport::Parse(status.body);
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(report.value().ToText(), status.body);
  EXPECT_EQ(report.value().vehicles.size(), 2u);
  ASSERT_FALSE(report.value().other_lines.empty());
  EXPECT_EQ(report.value().other_lines.front().first, "local_vehicles");
  const auto lines = VehicleLines(status.body);
  ASSERT_EQ(lines.size(), 2u) << status.body;
  // The physical tank got on the south bridge, fell at the break and died there.
  ASSERT_FALSE(seen_on_bridge.empty()) << "the physical tank never stood on a deck";
  EXPECT_NE(seen_on_bridge.at(0).at("on_bridge"), "-");
  EXPECT_EQ(lines.at(0).at("model"), "physical");
  EXPECT_EQ(lines.at(0).at("alive"), "0") << status.body;
  EXPECT_EQ(lines.at(0).at("damage"), "destroyed");
  EXPECT_LT(std::stod(lines.at(0).at("x_m")), 140.0) << "past the break";
  // The light tank keeps the thesis's rules: it drops at the break, survives and drives on.
  EXPECT_EQ(lines.at(1).at("model"), "light");
  EXPECT_EQ(lines.at(1).at("alive"), "1") << status.body;
  EXPECT_GT(std::stod(lines.at(1).at("x_m")), 180.0);

  // The dead tank refuses commands, with a message; the live one is still driven and clamped.
  const ControlReply dead = node.Handle("drive 0 5 0");
  EXPECT_FALSE(dead.ok);
  EXPECT_NE(dead.error.find("destroyed"), std::string::npos) << dead.error;
  const ControlReply clamped = node.Handle("drive 1 1e30 0");
  ASSERT_TRUE(clamped.ok) << clamped.error;
  EXPECT_NE(clamped.body.find("clamped to"), std::string::npos) << clamped.body;

  // The render draws both (the dead one in its own colour) and writes the file.
  const std::string png = (dir_ / "map.png").string();
  const ControlReply render = node.Handle("render " + png);
  ASSERT_TRUE(render.ok) << render.error;
  EXPECT_GT(std::filesystem::file_size(png), 0u);
}

TEST_F(NodeAppTest, SpawnsListsAndRemovesVehiclesAtRunTime) {
  const ExerciseConfig exercise =
      Exercise("[[node.vehicle]]\ntype = \"tank\"\nx_m = 50\nz_m = 100\n", false);
  NodeApp node(exercise, exercise.nodes[0]);
  node.Start(0);
  node.Tick(33, 0.033);
  ControlReply r = node.Handle("spawn jeep 120 80 90 light");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, "1");
  ASSERT_EQ(node.vehicles().size(), 2u);
  EXPECT_EQ(node.vehicles()[1].model(), VehicleModel::kLight);
  node.Tick(66, 0.033);
  r = node.Handle("vehicles");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NE(r.body.find("local 0 1:1:1 tank owner=1:1"), std::string::npos) << r.body;
  EXPECT_NE(r.body.find("local 1 1:1:2 jeep owner=1:1 x_m=120.00"), std::string::npos) << r.body;
  // Refused, changing nothing: an unknown type, a place off the terrain, a missing vehicle.
  r = node.Handle("spawn boat 10 10 0");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("boat"), std::string::npos) << r.error;
  EXPECT_FALSE(node.Handle("spawn tank 5000 10 0").ok);
  r = node.Handle("remove 2");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("vehicle 2 does not exist (this node has 2)"), std::string::npos);
  EXPECT_EQ(node.vehicles().size(), 2u);
  // Removing the tank moves the jeep to index 0; its entity ID stays.
  ASSERT_TRUE(node.Handle("remove 0").ok);
  ASSERT_EQ(node.vehicles().size(), 1u);
  EXPECT_EQ(node.vehicles()[0].type_name(), "jeep");
  r = node.Handle("vehicles");
  EXPECT_NE(r.body.find("local 0 1:1:2 jeep"), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find("tank"), std::string::npos) << r.body;
  r = node.Handle("status");
  EXPECT_NE(r.body.find("local_vehicles 1\nremote_vehicles 0"), std::string::npos) << r.body;
  // The first states and the removal were sent.
  EXPECT_GE(node.sharing().sent(), 3u);
}

TEST_F(NodeAppTest, ABulldozerCutsCarriesAndSetsDownThroughEarthMoves) {
  // A 64 m square at 1 m spacing: blade work wants posts closer than the blade is wide.
  const std::string text = fmt::format(
      "[exercise]\nname = \"node-app\"\ntransport = \"memq://\"\nrun_dir = \"{}\"\n"
      "[auth]\nmode = \"none\"\n"
      "[terrain]\nposts_per_side = 65\nspacing_m = 1\nrelief_m = 0\n"
      "[protocol]\nrequire_server = false\nmax_feature_period_ms = 50\nsilence_ms = 200\n"
      "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n",
      dir_.string());
  const ExerciseConfig exercise = ParseExerciseConfig(text, "ex.toml", dir_);
  NodeApp node(exercise, exercise.nodes[0]);
  node.Start(0);
  int64_t t = 0;
  auto run = [&](double seconds) {
    for (int k = 0; k < static_cast<int>(seconds * 30); ++k) node.Tick(t += 33, 0.033);
  };
  run(1.0);
  ASSERT_TRUE(node.ready());
  ASSERT_TRUE(node.Handle("spawn bulldozer 10 32 0 light").ok);
  ASSERT_TRUE(node.Handle("spawn tank 10 10 0 light").ok);
  // Refused, naming the value: too deep, no blade, no such vehicle, a bad position.
  ControlReply r = node.Handle("blade 0 down 0.8");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("blade depth_m = 0.8 is outside [0, 0.5]"), std::string::npos) << r.error;
  r = node.Handle("blade 1 down 0.2");
  EXPECT_NE(r.error.find("vehicle 1 is a tank, which has no blade"), std::string::npos) << r.error;
  r = node.Handle("blade 2 up");
  EXPECT_NE(r.error.find("vehicle 2 does not exist"), std::string::npos) << r.error;
  r = node.Handle("blade 0 sideways");
  EXPECT_NE(r.error.find("blade takes <vehicle> down <depth_m> or <vehicle> up"), std::string::npos)
      << r.error;
  r = node.Handle("blade 0 down deep");
  EXPECT_NE(r.error.find("depth_m"), std::string::npos) << r.error;
  EXPECT_EQ(node.blade_post_changes(), 0);
  const std::string bare = node.replica().Digest();
  r = node.Handle("blade 0 down 0.2");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, "blade down 0.2 m");
  ASSERT_TRUE(node.Handle("drive 0 1.5 0").ok);
  run(8.0);
  ASSERT_TRUE(node.Handle("blade 0 up").ok);
  run(1.0);
  ASSERT_TRUE(node.Handle("drive 0 0 0").ok);
  run(0.5);
  EXPECT_GT(node.blade_post_changes(), 50);
  EXPECT_NE(node.replica().Digest(), bare);
  const Terrain& terrain = node.replica().terrain();
  // A cut 0.2 m deep behind the blade, and every millimetre of it set down again.
  EXPECT_NEAR(terrain.ElevationAt(16.0, 32.0), -0.2, 0.03);
  int64_t sum = 0;
  for (int j = 0; j < 65; ++j) {
    for (int i = 0; i < 65; ++i) sum += terrain.BladeDeltaMm(i, j);
  }
  EXPECT_EQ(sum, 0);
}

// A tank and a group of 12 trucks (physical, the default): the trucks wander (the same way in two
// runs), are listed, counted and shared like the tank; a drive command hands one to its operator.
TEST_F(NodeAppTest, AGroupWandersDeterministicallyIsSharedAndCountedAndADriveTakesOneOver) {
  const ExerciseConfig exercise = Exercise(
      "[[node.vehicle]]\ntype = \"tank\"\nx_m = 50\nz_m = 100\n"
      "[[node.group]]\ntype = \"truck\"\ncount = 12\nseed = 3\n"
      "area = { x_min_m = 40, x_max_m = 300, z_min_m = 20, z_max_m = 280 }\n",
      false);
  std::vector<VehiclePose> first_run;
  for (int run = 0; run < 2; ++run) {
    NodeApp node(exercise, exercise.nodes[0]);
    ASSERT_EQ(node.vehicles().size(), 13u);
    EXPECT_EQ(node.autonomous_count(), 12);
    EXPECT_FALSE(node.autonomous(0));
    EXPECT_EQ(node.vehicles()[1].model(), VehicleModel::kPhysical);
    std::vector<VehiclePose> start;
    for (const SimulatedVehicle& v : node.vehicles()) start.push_back(v.pose());
    node.Start(0);
    for (int64_t ms = 33; ms <= 20000; ms += 33) node.Tick(ms, 0.033);
    const double size_x_m = exercise.terrain_size_x_m(), size_z_m = exercise.terrain_size_z_m();
    for (size_t i = 0; i < node.vehicles().size(); ++i) {
      const VehiclePose p = node.vehicles()[i].pose();
      const double moved_m = std::hypot(p.x_m - start[i].x_m, p.z_m - start[i].z_m);
      if (i == 0) {
        EXPECT_EQ(moved_m, 0.0);  // the tank is nobody's to drive
      } else {
        EXPECT_GT(moved_m, 10.0) << "truck " << i;
        EXPECT_GT(std::min({p.x_m, p.z_m, size_x_m - p.x_m, size_z_m - p.z_m}), 5.0)
            << "truck " << i;
      }
      if (run == 0) {
        first_run.push_back(p);
      } else {
        EXPECT_EQ(p.x_m, first_run[i].x_m) << i;
        EXPECT_EQ(p.z_m, first_run[i].z_m) << i;
        EXPECT_EQ(p.heading_rad, first_run[i].heading_rad) << i;
      }
    }
    if (run == 1) {
      ControlReply r = node.Handle("vehicles");
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_NE(r.body.find("local 12 1:1:13 truck owner=1:1"), std::string::npos) << r.body;
      r = node.Handle("status");
      EXPECT_NE(r.body.find("local_vehicles 13\n"), std::string::npos) << r.body;
      EXPECT_NE(r.body.find("autonomous_vehicles 12"), std::string::npos) << r.body;
      // Every vehicle's first state went out, and the wandering ones' turns since.
      EXPECT_GT(node.sharing().sent(), 13u);
      // Driving truck 5 makes it the operator's: it stops wandering and holds the command.
      ASSERT_TRUE(node.Handle("drive 5 0 0").ok);
      EXPECT_FALSE(node.autonomous(5));
      // The physical truck brakes within its grip: a few seconds from its wandering speed.
      for (int64_t ms = 20033; ms <= 25000; ms += 33) node.Tick(ms, 0.033);
      EXPECT_EQ(node.vehicles()[5].commanded_speed_mps(), 0.0);
      EXPECT_NEAR(node.vehicles()[5].pose().speed_mps, 0.0, 0.05);
      r = node.Handle("status");
      EXPECT_NE(r.body.find("autonomous_vehicles 11"), std::string::npos) << r.body;
    }
  }
}

TEST_F(NodeAppTest, RefusesADriveThatIsNotFiniteAndClampsOneOutOfRange) {
  const ExerciseConfig exercise =
      Exercise("[[node.vehicle]]\ntype = \"jeep\"\nx_m = 50\nz_m = 50\n", false);
  NodeApp node(exercise, exercise.nodes[0]);
  ControlReply r = node.Handle("drive 0 nan 0");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("speed_mps \"nan\" is not a finite number"), std::string::npos) << r.error;
  r = node.Handle("drive 0 1e30 1e9");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NE(r.body.find("the jeep's top speed"), std::string::npos) << r.body;
  EXPECT_NE(r.body.find("heading rate"), std::string::npos) << r.body;
  EXPECT_DOUBLE_EQ(node.vehicles()[0].commanded_speed_mps(),
                   node.vehicles()[0].type().base.max_speed_mps);
  r = node.Handle("drive 1 1 0");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("vehicle 1 does not exist"), std::string::npos) << r.error;
}

// A ground 320 m east by 160 m north (33 x 17 posts): a group wanders it without leaving it, a
// crater at the far east corner is placed, one past the north edge is refused naming the bound
// (by the replica, and by the PDU validation the exercise's bus applies), and the map has the
// ground's aspect.
TEST_F(NodeAppTest, ARectangularExerciseRunsOnItsWholeGroundAndNoFurther) {
  const std::string text = fmt::format(
      "[exercise]\nname = \"node-app\"\ntransport = \"memq://\"\nrun_dir = \"{}\"\n"
      "[auth]\nmode = \"none\"\n"
      "[terrain]\nposts_x = 33\nposts_z = 17\nspacing_m = 10\nrelief_m = 4\n"
      "[protocol]\nrequire_server = false\nmax_feature_period_ms = 50\nsilence_ms = 200\n"
      "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
      "[[node.vehicle]]\ntype = \"tank\"\nx_m = 300\nz_m = 140\n"
      "[[node.group]]\ntype = \"jeep\"\ncount = 6\nseed = 5\n",
      dir_.string());
  const ExerciseConfig exercise = ParseExerciseConfig(text, "ex.toml", dir_);
  NodeApp node(exercise, exercise.nodes[0]);
  const HeightGrid& ground = node.replica().terrain().ground();
  ASSERT_EQ(ground.posts_x(), 33);
  ASSERT_EQ(ground.posts_z(), 17);
  ASSERT_EQ(node.vehicles().size(), 7u);
  node.Start(0);
  int64_t t = 0;
  for (int k = 0; k < 30 * 20; ++k) node.Tick(t += 33, 0.033);
  ASSERT_TRUE(node.ready());
  double moved_m = 0.0;
  for (size_t i = 1; i < node.vehicles().size(); ++i) {
    const VehiclePose p = node.vehicles()[i].pose();
    EXPECT_GT(std::min({p.x_m, p.z_m, 320.0 - p.x_m, 160.0 - p.z_m}), 0.0) << "jeep " << i;
    moved_m = std::max(moved_m, p.x_m);
  }
  EXPECT_GT(moved_m, 170.0) << "no jeep went east of where a 160 m square would end";

  // A crater at the far east corner, its rim reaching both far edges.
  ControlReply r = node.Handle("crater 315 155 5");
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(node.replica().live_feature_count(), 1u);
  // Past the north edge (though well inside a 320 m square), and past the east edge.
  r = node.Handle("crater 100 165 4");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("off the terrain [0, 320] x [0, 160] m"), std::string::npos) << r.error;
  r = node.Handle("crater 318 100 4");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("leaves the terrain [0, 320] x [0, 160] m"), std::string::npos) << r.error;
  EXPECT_EQ(node.replica().live_feature_count(), 1u);
  // What arrives from another node is held to the same bounds by the exercise's bus.
  const ProcessTransport bus = MakeProcessTransport(exercise, exercise.nodes[0]);
  auto validate = [&](const FeatureParams& params) {
    FeaturePdu f;
    f.id = {1, 2, 1};
    f.change = {{1, 2}, 1, 1};
    f.params = params;
    dtpdu::construct_t pdu = ToConstruct(f);
    pdu.header.protocol_version = kProtocolVersion;
    pdu.header.exercise_id = exercise.exercise_id;
    pdu.header.pdu_type = static_cast<uint8_t>(PduTraits<dtpdu::construct_t>::kType);
    pdu.sender.site = 1;
    pdu.sender.host = 2;
    pdu.sender_seq = 1;
    return Validate(pdu, bus.bus->validation_context());
  };
  const std::optional<Rejection> refused = validate(FeatureParams::Crater(100, 165, 4));
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RejectReason::kOffTerrain);
  EXPECT_EQ(refused->detail, "z = 165 m is outside [0, 160] m");
  const std::optional<Rejection> corner = validate(FeatureParams::Crater(315, 155, 4));
  EXPECT_FALSE(corner.has_value()) << corner->detail;

  // The map is as wide as the ground's longer side allows and half as high.
  const std::string png = (dir_ / "rect.png").string();
  r = node.Handle("render " + png);
  ASSERT_TRUE(r.ok) << r.error;
  const Result<Image> image = ReadPng(png);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image.value().width(), kMapRenderPx);
  EXPECT_EQ(image.value().height(), kMapRenderPx / 2);
}

}  // namespace
}  // namespace dt
