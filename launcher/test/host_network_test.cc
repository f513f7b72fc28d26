// Tests the hosts mode: carrier URLs and the generated Cyclone DDS configuration, and (as root)
// a LAN and a WAN made, cut, healed and removed.
#include "launcher/host_network.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace dt {
namespace {

const std::string kExercise =
    "[exercise]\nname = \"e\"\nrun_dir = \"/tmp/unused\"\n[auth]\nmode = \"none\"\n[terrain]\n"
    "[server]\nname = \"server\"\nsite = 1\nhost = 100\n"
    "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
    "[[node]]\nname = \"node-2\"\nsite = 2\nhost = 1\n";

ExerciseConfig Exercise(const std::string& mode) {
  ExerciseConfig e = ParseExerciseConfig(kExercise, "e.toml", "/base");
  ApplyHostsOverride(e, mode);
  return e;
}

// What a shell command prints.
std::string Output(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return out;
  char buf[512];
  while (fgets(buf, sizeof buf, p) != nullptr) out += buf;
  pclose(p);
  return out;
}

bool NamespaceExists(const std::string& ns) {
  return std::filesystem::exists(std::filesystem::path("/run/netns") / ns);
}

TEST(HostNetworkTest, UdpmGoesOutAtTtl1) {
  EXPECT_EQ(HostsUdpmUrl("udpm://239.255.76.67:7667?ttl=0"), "udpm://239.255.76.67:7667?ttl=1");
  EXPECT_EQ(HostsUdpmUrl("udpm://239.255.76.67:7667"), "udpm://239.255.76.67:7667?ttl=1");
  EXPECT_EQ(HostsUdpmUrl("udpm://239.1.1.1:7000?recv_buf_size=1000"),
            "udpm://239.1.1.1:7000?recv_buf_size=1000&ttl=1");
  EXPECT_EQ(HostsUdpmUrl("udpm://239.1.1.1:7000?ttl=5&recv_buf_size=1000"),
            "udpm://239.1.1.1:7000?ttl=1&recv_buf_size=1000");
}

TEST(HostNetworkTest, CycloneConfigDiscoversByMulticastOnALanAndByPeersOnAWan) {
  const std::string lan = HostsCycloneConfig(HostsMode::kLan, {});
  EXPECT_NE(lan.find("<NetworkInterface name=\"dt0\"/>"), std::string::npos) << lan;
  EXPECT_NE(lan.find("<AllowMulticast>true</AllowMulticast>"), std::string::npos) << lan;
  EXPECT_EQ(lan.find("<Peers>"), std::string::npos) << lan;
  const std::string wan = HostsCycloneConfig(HostsMode::kWan, {"10.77.1.1", "10.77.2.1"});
  EXPECT_NE(wan.find("<AllowMulticast>false</AllowMulticast>"), std::string::npos) << wan;
  EXPECT_NE(wan.find("<Peer address=\"10.77.1.1\"/>"), std::string::npos) << wan;
  EXPECT_NE(wan.find("<Peer address=\"10.77.2.1\"/>"), std::string::npos) << wan;
  EXPECT_NE(wan.find("<MaxAutoParticipantIndex>"), std::string::npos) << wan;
}

TEST(HostNetworkTest, HostsOverrideNamesABadMode) {
  EXPECT_EQ(Exercise("").hosts.mode, HostsMode::kNone);
  EXPECT_EQ(Exercise("lan").hosts.mode, HostsMode::kLan);
  try {
    Exercise("cloud");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cloud"), std::string::npos) << e.what();
  }
}

TEST(HostNetworkTest, LanIsMadeCutHealedAndRemoved) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to make network namespaces";
  const std::string server_ns = "dt" + std::to_string(getpid()) + "-server";
  {
    HostNetwork net(Exercise("lan"));
    EXPECT_EQ(net.Namespace("server"), server_ns);
    EXPECT_TRUE(NamespaceExists(server_ns));
    EXPECT_EQ(net.Address("node-2"), "10.77.2.1");
    EXPECT_EQ(net.OnHost("node-1", {"dt_node", "--name", "node-1"}),
              (std::vector<std::string>{"ip", "netns", "exec", net.Namespace("node-1"), "dt_node",
                                        "--name", "node-1"}));
    // Bridge ports are p<i>, i in the exercise's order: server p0, node-1 p1, node-2 p2.
    const std::string lan = "dt" + std::to_string(getpid()) + "-lan";
    auto port = [&](const std::string& p) { return Output("ip -n " + lan + " -o link show " + p); };
    EXPECT_NE(port("p1").find("master br0 state UP"), std::string::npos) << port("p1");
    net.Cut({"node-1"}, {"server", "node-2"});
    EXPECT_NE(port("p1").find("state DOWN"), std::string::npos) << port("p1");
    net.Cut({"server", "node-2"}, {"node-1"});  // a LAN splits its bridge
    EXPECT_NE(port("p2").find("master br1"), std::string::npos) << port("p2");
    net.Heal();
    for (const char* p : {"p0", "p1", "p2"}) {
      EXPECT_NE(port(p).find("master br0 state UP"), std::string::npos) << port(p);
    }
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("dt-hosts-test-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    EXPECT_EQ(net.CarrierUrl("dds://0?config=x.xml&durable=1", dir),
              "dds://0?config=" + (dir / "cyclonedds-hosts.xml").string() + "&durable=1");
    EXPECT_TRUE(std::filesystem::exists(dir / "cyclonedds-hosts.xml"));
    EXPECT_THROW(net.CarrierUrl("memq://", dir), std::invalid_argument);
    std::filesystem::remove_all(dir);
  }
  EXPECT_FALSE(NamespaceExists(server_ns));
}

TEST(HostNetworkTest, WanHasARouterAndCutsOneHostAtATime) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to make network namespaces";
  const std::string router = "dt" + std::to_string(getpid()) + "-router";
  {
    HostNetwork net(Exercise("wan"));
    EXPECT_TRUE(NamespaceExists(router));
    EXPECT_NO_THROW(net.Cut({"node-2"}, {"server", "node-1"}));
    EXPECT_THROW(net.Cut({"server", "node-1"}, {"node-2"}), std::runtime_error);
    EXPECT_NO_THROW(net.Heal());
  }
  EXPECT_FALSE(NamespaceExists(router));
}

TEST(HostNetworkTest, RemovesWhatADeadLauncherLeftWithTheProcessesOnIt) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to make network namespaces";
  // A PID no process has: a child that has exited and been reaped.
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  ASSERT_GT(dead, 0);
  ASSERT_EQ(waitpid(dead, nullptr, 0), dead);
  const std::string ns = "dt" + std::to_string(dead) + "-node-1";
  ASSERT_EQ(std::system(("ip netns add " + ns).c_str()), 0);
  // What its launcher left running on the host.
  const pid_t orphan = fork();
  if (orphan == 0) {
    execlp("ip", "ip", "netns", "exec", ns.c_str(), "sleep", "60", static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(orphan, 0);
  // It is on the host once `ip netns pids` lists it (exec may take a moment).
  for (int i = 0; i < 500; ++i) {
    FILE* p = popen(("ip netns pids " + ns).c_str(), "r");
    char buf[64] = {};
    const bool listed = p != nullptr && fgets(buf, sizeof buf, p) != nullptr;
    if (p != nullptr) pclose(p);
    if (listed) break;
    usleep(10000);
  }
  HostNetwork::RemoveStale();
  EXPECT_FALSE(NamespaceExists(ns));
  int status = 0;
  ASSERT_EQ(waitpid(orphan, &status, 0), orphan);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
}

TEST(HostNetworkTest, RefusesAnAddressThatDoesNotFit) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to make network namespaces";
  ExerciseConfig e = Exercise("lan");
  e.nodes[0].address.host = 300;
  try {
    HostNetwork net(e);
    FAIL() << "accepted";
  } catch (const std::runtime_error& err) {
    EXPECT_NE(std::string(err.what()).find("node-1 is 1:300"), std::string::npos) << err.what();
  }
}

}  // namespace
}  // namespace dt
