// Tests the hosts mode: carrier URLs and the generated Cyclone DDS configuration, and (as root)
// a LAN and a WAN made, cut, healed and removed.
#include "launcher/host_network.h"

#include <unistd.h>

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
    EXPECT_NO_THROW(net.Cut({"node-1"}, {"server", "node-2"}));
    EXPECT_NO_THROW(net.Cut({"server", "node-2"}, {"node-1"}));  // a LAN splits its bridge
    EXPECT_NO_THROW(net.Heal());
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
