#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "runtime/control_client.h"
#include "runtime/control_command.h"
#include "runtime/control_server.h"
#include "runtime/test/map_actions.h"

namespace dt {
namespace {

std::filesystem::path TempSocket(const std::string& tag) {
  return std::filesystem::temp_directory_path() / fmt::format("dt-ctl-{}-{}.sock", tag, ::getpid());
}

// Runs a server's Poll loop on its own thread until stopped.
class ServingThread {
 public:
  explicit ServingThread(ControlServer& server)
      : thread_([this, &server] {
          while (!stop_) server.Poll(20);
        }) {}
  ~ServingThread() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(ControlProtocolTest, EncodesStatusBodyAndEscapesDots) {
  EXPECT_EQ(EncodeControlReply(ControlReply::Ok()), "ok\n.\n");
  EXPECT_EQ(EncodeControlReply(ControlReply::Ok("a\n.\nb")), "ok\na\n..\nb\n.\n");
  EXPECT_EQ(EncodeControlReply(ControlReply::Fail("bad\nthing")), "error: bad thing\n.\n");
}

TEST(ControlCommandTest, ParsesEveryVerb) {
  Result<ControlCommand> c = ParseControlCommand("crater 100 200 5");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().verb, ControlVerb::kCreate);
  EXPECT_EQ(c.value().params, FeatureParams::Crater(100, 200, 5));

  c = ParseControlCommand("  berm 10 20 90 30 4 2 ");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_NEAR(c.value().params.direction_rad, 1.5707963267948966, 1e-12);
  EXPECT_DOUBLE_EQ(c.value().params.height_m[0], 2.0);

  c = ParseControlCommand("bridge 100 100 0 8 20 60 20 6 6");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_DOUBLE_EQ(c.value().params.length_m[0], 60.0);
  EXPECT_DOUBLE_EQ(c.value().params.length_m[1], 20.0);

  c = ParseControlCommand("update 1:2:3 radius_m=8 x_m=4");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().target, (FeatureId{1, 2, 3}));
  ASSERT_EQ(c.value().edit.values.size(), 2u);

  c = ParseControlCommand("breach 1:2:3 10 5");
  ASSERT_TRUE(c);
  EXPECT_DOUBLE_EQ(c.value().gap_width_m, 5.0);
  c = ParseControlCommand("drive 0 5 -90");
  ASSERT_TRUE(c);
  EXPECT_NEAR(c.value().heading_rate_rad_s, -1.5707963267948966, 1e-12);
  c = ParseControlCommand("partition 1:1 1:2");
  ASSERT_TRUE(c);
  EXPECT_EQ(c.value().nodes.size(), 2u);
  EXPECT_EQ(ParseControlCommand("loss 0.3").value().drop_probability, 0.3);
  EXPECT_EQ(ParseControlCommand("render /tmp/x.png").value().path, "/tmp/x.png");
  for (const char* v : {"status", "digest", "features", "heal", "ping", "quit", "vehicles"}) {
    EXPECT_TRUE(ParseControlCommand(v)) << v;
  }
  c = ParseControlCommand("vehicles --owner 1:2 --offset 30 --limit 5");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().vehicle_page, (VehiclePage{"1:2", 30, 5}));
  EXPECT_EQ(ParseControlCommand("vehicles --all").value().vehicle_page, VehiclePage{});
  EXPECT_EQ(ParseControlCommand("vehicles").value().vehicle_page, VehiclePage{});
  for (const char* bad :
       {"vehicles --limit 0", "vehicles --limit", "vehicles --offset -1", "vehicles --owner node-1",
        "vehicles --limit 5 --all", "vehicles --offset 1 --offset 2", "vehicles everything"}) {
    EXPECT_FALSE(ParseControlCommand(bad)) << bad;
  }
  EXPECT_NE(ParseControlCommand("vehicles --limit x").error().message.find("\"x\""),
            std::string::npos);
  c = ParseControlCommand("spawn jeep 10 20 90 light");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().verb, ControlVerb::kSpawn);
  EXPECT_EQ(c.value().spawn.type, "jeep");
  EXPECT_EQ(c.value().spawn.model, "light");
  EXPECT_DOUBLE_EQ(c.value().spawn.z_m, 20.0);
  EXPECT_NEAR(c.value().spawn.heading_rad, 1.5707963267948966, 1e-12);
  EXPECT_EQ(ParseControlCommand("spawn tank 1 2 0").value().spawn.model, "physical");
  c = ParseControlCommand("remove 4");
  ASSERT_TRUE(c);
  EXPECT_EQ(c.value().verb, ControlVerb::kRemove);
  EXPECT_EQ(c.value().vehicle, 4);
}

TEST(ControlCommandTest, RefusesBadCommandsWithTheValue) {
  auto err = [](const char* line) {
    Result<ControlCommand> c = ParseControlCommand(line);
    return c ? std::string() : c.error().message;
  };
  EXPECT_NE(err("crater 1 2").find("takes 3 arguments, got 2"), std::string::npos);
  EXPECT_NE(err("crater 1 2 abc").find("radius_m \"abc\""), std::string::npos);
  EXPECT_NE(err("crater 1 2 nan").find("not a finite number"), std::string::npos);
  EXPECT_NE(err("drive 0 -inf 0").find("speed_mps \"-inf\" is not a finite number"),
            std::string::npos);
  EXPECT_NE(err("drive 0 1 -nan").find("heading_rate_deg_s \"-nan\" is not a finite number"),
            std::string::npos);
  EXPECT_NE(err("crater 1 2 -4").find("radius"), std::string::npos) << err("crater 1 2 -4");
  // The documented bounds of terrain/feature_params.h reach the command's reply.
  EXPECT_NE(err("crater 50 50 4.9e-324").find("crater radius_m = 5e-324 is outside [0.01, 200]"),
            std::string::npos)
      << err("crater 50 50 4.9e-324");
  EXPECT_EQ(err("berm 10 10 1e300 30 4 2"),
            "direction_deg=1e+300 is outside [-360, 360] (one turn either way)");
  EXPECT_EQ(err("berm 10 10 -360 30 4 2"), "");
  EXPECT_NE(err("bridge 100 100 0 8 20 60 20 6 0.001").find("bridge height_m[1] = 0.001"),
            std::string::npos);
  EXPECT_NE(err("destroy 1:2").find("\"1:2\""), std::string::npos);
  EXPECT_NE(err("destroy 1:2:0").find("number 0"), std::string::npos);
  EXPECT_NE(err("destroy 1:70000:3").find("host \"70000\""), std::string::npos);
  EXPECT_NE(err("update 1:1:1 radius").find("not key=value"), std::string::npos);
  EXPECT_NE(err("breach 1:1:1 5 0").find("gap_width_m > 0"), std::string::npos);
  EXPECT_NE(err("loss 2").find("outside [0, 1]"), std::string::npos);
  EXPECT_NE(err("status now").find("no arguments"), std::string::npos);
  EXPECT_NE(err("fly 1 2").find("unknown command \"fly\""), std::string::npos);
  EXPECT_NE(err("spawn tank 1 2").find("spawn takes"), std::string::npos);
  EXPECT_NE(err("spawn tank 1 nan 0").find("z_m \"nan\""), std::string::npos);
  EXPECT_NE(err("spawn tank 1 2 0 heavy").find("\"heavy\" is neither"), std::string::npos);
  EXPECT_NE(err("remove -1").find("not an index"), std::string::npos);
  EXPECT_NE(err("remove 1.5").find("not an index"), std::string::npos);
  EXPECT_NE(err("").find("empty"), std::string::npos);
}

TEST(ControlVerbTableTest, EveryVerbHasOneRowAndEachFeatureTypeItsCreateWord) {
  std::map<ControlVerb, int> rows;
  std::set<std::string_view> create_words, words;
  for (const ControlVerbSpec& spec : ControlVerbTable()) {
    ++rows[spec.verb];
    EXPECT_TRUE(words.insert(spec.word).second) << spec.word << " has two rows";
    EXPECT_FALSE(spec.help.empty()) << spec.word;
    EXPECT_NE(spec.parse, nullptr) << spec.word;
    if (spec.verb == ControlVerb::kCreate) create_words.insert(spec.word);
  }
  for (int v = 0; v < static_cast<int>(ControlVerb::kCount); ++v) {
    if (static_cast<ControlVerb>(v) == ControlVerb::kCreate) continue;
    EXPECT_EQ(rows[static_cast<ControlVerb>(v)], 1) << "ControlVerb " << v;
  }
  EXPECT_EQ(rows.count(ControlVerb::kCount), 0u);
  // kCreate: one word per feature type but earth moves (blade work makes those).
  std::set<std::string_view> feature_types;
  for (FeatureType t : {FeatureType::kCrater, FeatureType::kBerm, FeatureType::kBridge,
                        FeatureType::kDitch, FeatureType::kBermLine, FeatureType::kArea}) {
    feature_types.insert(FeatureTypeName(t));
  }
  EXPECT_EQ(create_words, feature_types);
}

TEST(ControlVerbTableTest, EachWordReachesItsVerb) {
  for (const ControlVerbSpec& spec : ControlVerbTable()) {
    // Bare, most commands lack arguments; either way the word's own parser answered.
    Result<ControlCommand> c = ParseControlCommand(spec.word);
    if (c) {
      EXPECT_EQ(c.value().verb, spec.verb) << spec.word;
    } else {
      EXPECT_EQ(c.error().message.find("unknown command"), std::string::npos) << spec.word;
    }
  }
}

TEST(ControlVerbTableTest, UsageIsTheTextItHasAlwaysBeen) {
  EXPECT_EQ(ControlUsage(),
            "crater <x_m> <z_m> <radius_m> [<depth_m>]\n"
            "ditch side_run_m=<m> [spoil_height_m=<m> spoil_width_m=<m>] <x,z,depth,width> ...\n"
            "berm_line <x,z,height,width> <x,z,height,width> ...\n"
            "area <soil> [level_m=<m>] <x,z> <x,z> <x,z> ...\n"
            "berm <x_m> <z_m> <direction_deg> <length_m> <width_m> <height_m>\n"
            "bridge <x_m> <z_m> <direction_deg> <width_m> <ramp1_m> <span_m> <ramp2_m> "
            "<height1_m> <height2_m>\n"
            "update <site:host:number> <key>=<value> ...\n"
            "destroy <site:host:number>\n"
            "breach <site:host:number> <gap_start_m> <gap_width_m>\n"
            "drive <vehicle> <speed_mps> <heading_rate_deg_s>\n"
            "spawn <type> <x_m> <z_m> <heading_deg> [physical|light] | remove <vehicle>\n"
            "vehicles [--owner <site:host>] [--offset <n>] [--limit <n> | --all]\n"
            "blade <vehicle> down <depth_m> | blade <vehicle> up\n"
            "status | digest | features | ping | quit\n"
            "render <file.png>\n"
            "export <file.dtt> | import <file.dtt> (server)\n"
            "loss <drop_probability>\n"
            "partition <site:host> ... | heal");
  EXPECT_EQ(ParseControlCommand("fly").error().message,
            "unknown command \"fly\"; commands:\n" + ControlUsage());
  EXPECT_EQ(ParseControlCommand(" ").error().message,
            "empty command; commands:\n" + ControlUsage());
}

TEST(ControlCommandTest, BadFeatureCommandChangesNothing) {
  MapActions node;
  ASSERT_TRUE(RunFeatureCommand(ParseControlCommand("crater 10 10 3").value(), node).ok);
  const auto before = node.features;
  const FeatureId id = before.begin()->first;
  ControlReply r = RunFeatureCommand(
      ParseControlCommand("update " + id.ToString() + " radius_m=9 height_m=2").value(), node);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("height_m is not a key of a crater"), std::string::npos) << r.error;
  r = RunFeatureCommand(ParseControlCommand("update 1:1:99 radius_m=9").value(), node);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("1:1:99"), std::string::npos);
  r = RunFeatureCommand(ParseControlCommand("drive 3 1 0").value(), node);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(node.features, before);
  EXPECT_TRUE(node.drives.empty());

  r = RunFeatureCommand(ParseControlCommand("update " + id.ToString() + " radius_m=9").value(),
                        node);
  EXPECT_TRUE(r.ok) << r.error;
  EXPECT_DOUBLE_EQ(node.features.at(id).length_m[0], 9.0);
}

TEST(ControlCommandTest, DitchesBermLinesAreasAndDeepCratersParse) {
  Result<ControlCommand> c = ParseControlCommand(
      "ditch side_run_m=1.5 spoil_height_m=1 spoil_width_m=3 20,50,2,6 "
      "80,50,2.5,7");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().params, FeatureParams::Ditch({{20, 50, 2, 6}, {80, 50, 2.5, 7}}, 1.5, 1, 3));
  c = ParseControlCommand("berm_line 10,10,2,6 40,20,3,8 60,50,2,6");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().params.points.size(), 3u);
  c = ParseControlCommand("area water level_m=4.5 10,10 30,10 20,30");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().params, FeatureParams::Area({{10, 10, 0, 0}, {30, 10, 0, 0}, {20, 30, 0, 0}},
                                                  Material::kWater, 4.5));
  c = ParseControlCommand("crater 50 50 10 3");
  ASSERT_TRUE(c) << c.error().message;
  EXPECT_EQ(c.value().params, FeatureParams::DeepCrater(50, 50, 10, 3));
  auto err = [](const std::string& line) {
    Result<ControlCommand> r = ParseControlCommand(line);
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(err("ditch 20,50,2,6 80,50,2,6").find("a new ditch needs side_run_m"),
            std::string::npos)
      << err("ditch 20,50,2,6 80,50,2,6");
  EXPECT_NE(err("ditch side_run_m=4 20,50,2,6 80,50,2,6").find("ditch points[0].width_m = 6"),
            std::string::npos)
      << err("ditch side_run_m=4 20,50,2,6 80,50,2,6");
  EXPECT_NE(err("berm_line 10,10,2 40,20,3,8").find("is not x_m,z_m,height_m,width_m"),
            std::string::npos);
  EXPECT_NE(err("berm_line 10,10,2,x 40,20,3,8").find("points[0].width_m \"x\""), std::string::npos)
      << err("berm_line 10,10,2,x 40,20,3,8");
  EXPECT_NE(err("area lava 10,10 30,10 20,30").find("area soil \"lava\" is not a soil"),
            std::string::npos);
  EXPECT_NE(err("area mud level_m=2 10,10 30,10 20,30").find("a water level"), std::string::npos)
      << err("area mud level_m=2 10,10 30,10 20,30");
  EXPECT_NE(err("crater 50 50 10 -1").find("crater depth_m height_m[0] = -1"), std::string::npos)
      << err("crater 50 50 10 -1");
}

TEST(ControlCommandTest, AnUpdateGrowsALineByItsNextPoint) {
  MapActions node;
  ASSERT_TRUE(
      RunFeatureCommand(ParseControlCommand("berm_line 10,10,2,6 40,10,2,6").value(), node).ok);
  const FeatureId id = node.features.begin()->first;
  ControlReply r = RunFeatureCommand(
      ParseControlCommand("update " + id.ToString() +
                          " points[2].x_m=60 points[2].z_m=30 points[2].height_m=3 "
                          "points[2].width_m=7")
          .value(),
      node);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(node.features.at(id).points.size(), 3u);
  EXPECT_EQ(node.features.at(id).points[2], (FeaturePoint{60, 30, 3, 7}));
  // Skipping an index, or a key the line does not have, changes nothing.
  r = RunFeatureCommand(ParseControlCommand("update " + id.ToString() + " points[4].x_m=1").value(),
                        node);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("points[4].x_m is not a point key"), std::string::npos) << r.error;
  r = RunFeatureCommand(ParseControlCommand("update " + id.ToString() + " x_m=1").value(), node);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(node.features.at(id).points.size(), 3u);
}

TEST(ControlCommandTest, ADriveSaysWhichValuesTheVehicleClamped) {
  const VehicleType tank = TankType();
  MapActions node;
  ControlReply r = RunFeatureCommand(ParseControlCommand("drive 0 1e30 0").value(), node);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, fmt::format("speed 1e+30 m/s clamped to {} m/s, the tank's top speed",
                                tank.max_speed_mps));
  EXPECT_EQ(node.vehicle.commanded_speed_mps(), tank.max_speed_mps);

  r = RunFeatureCommand(ParseControlCommand("drive 0 -50 0").value(), node);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, fmt::format("speed -50 m/s clamped to {} m/s, the tank's top reverse speed",
                                -tank.max_reverse_speed_mps));

  r = RunFeatureCommand(ParseControlCommand("drive 0 5 -1000").value(), node);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, fmt::format("heading rate -1000 deg/s clamped to {:.6g} deg/s, the tank's top "
                                "turn rate",
                                -tank.max_turn_rate_rad_s * 180.0 / std::numbers::pi));
  EXPECT_EQ(node.vehicle.commanded_speed_mps(), 5.0);

  // Within the limits: nothing to say.
  r = RunFeatureCommand(ParseControlCommand("drive 0 -3 20").value(), node);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.body, "");
  EXPECT_EQ(node.vehicle.commanded_speed_mps(), -3.0);
}

TEST(ControlServerTest, AnswersRequestsOverTheSocket) {
  const std::filesystem::path path = TempSocket("rt");
  int calls = 0;
  ControlServer server(path, [&](std::string_view line) {
    ++calls;
    if (line == "multi") return ControlReply::Ok("x\n.\ny");
    if (line == "bad") return ControlReply::Fail("no good");
    return ControlReply::Ok(std::string("echo ") + std::string(line));
  });
  ASSERT_TRUE(std::filesystem::exists(path));
  {
    ServingThread serving(server);
    Result<ControlReply> r = CallControl(path, "hello there", 5000);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_TRUE(r.value().ok);
    EXPECT_EQ(r.value().body, "echo hello there");
    r = CallControl(path, "multi", 5000);
    ASSERT_TRUE(r);
    EXPECT_EQ(r.value().body, "x\n.\ny");
    r = CallControl(path, "bad", 5000);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r.value().ok);
    EXPECT_EQ(r.value().error, "no good");
    r = CallControl(path, std::string(kMaxControlLineBytes + 10, 'a'), 5000);
    ASSERT_TRUE(r);
    EXPECT_FALSE(r.value().ok);
    EXPECT_NE(r.value().error.find("exceeds"), std::string::npos);
    r = CallControl(path, "two\nlines", 5000);
    EXPECT_FALSE(r);
  }
  EXPECT_EQ(calls, 3);  // the over-long line never reached the handler
}

TEST(ControlServerTest, ClientTimesOutWhenNobodyAnswers) {
  const std::filesystem::path path = TempSocket("to");
  ControlServer server(path, [](std::string_view) { return ControlReply::Ok(); });
  // Nobody polls: the connection is queued but never answered.
  Result<ControlReply> r = CallControl(path, "ping", 100);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("no reply"), std::string::npos) << r.error().message;
}

TEST(ControlServerTest, ReplacesStaleSocketButNotALiveOne) {
  const std::filesystem::path path = TempSocket("stale");
  {
    // A socket file left by a killed process: bound, then closed without unlinking.
    const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strcpy(addr.sun_path, path.c_str());
    ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
    close(fd);
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  auto server = std::make_unique<ControlServer>(
      path, [](std::string_view) { return ControlReply::Ok("fresh"); });
  EXPECT_THROW(ControlServer(path, [](std::string_view) { return ControlReply::Ok(); }),
               std::runtime_error);
  server.reset();
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_THROW(
      ControlServer(std::string(200, 'p'), [](std::string_view) { return ControlReply::Ok(); }),
      std::invalid_argument);
  Result<ControlReply> r = CallControl(path, "ping", 100);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("cannot connect"), std::string::npos);
}

}  // namespace
}  // namespace dt
