// Runs dt_launch itself (under a Supervisor) on an exercise whose processes are fake children.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "launcher/supervisor.h"

namespace dt {
namespace {

std::filesystem::path WriteExercise(const std::string& tag) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dt-launch-" + tag + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ex.toml")
      << "[exercise]\nname = \"fakes\"\nrun_dir = \"" << dir.string()
      << "\"\n[auth]\nmode = \"none\"\n[terrain]\n[server]\nname = \"server\"\nsite = 1\n"
         "host = 100\n[standby]\nname = \"standby\"\nsite = 1\n"
         "host = 101\n[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
         "[[node]]\nname = \"node-2\"\nsite = 1\nhost = 2\n";
  return dir / "ex.toml";
}

TEST(LaunchTest, StartsAllWaitsForReadyAndStopsOnSigterm) {
  std::vector<std::string> out;
  Supervisor sup([&](const std::string&, std::string_view line) { out.emplace_back(line); });
  const std::filesystem::path ex = WriteExercise("ok");
  sup.Start("fakes", {DT_LAUNCH, "--config", ex.string(), "--node-bin", DT_FAKE_CHILD,
                      "--server-bin", DT_FAKE_CHILD, "--ready-timeout-s", "30"});
  ASSERT_TRUE(sup.WaitReady({"fakes"}, 60000));
  // Every child's READY came before the launcher's, each prefixed with its name.
  for (const char* n : {"server", "standby", "node-1", "node-2"}) {
    EXPECT_NE(std::find(out.begin(), out.end(), fmt::format("[{}] READY {}", n, n)), out.end())
        << n;
  }
  sup.Signal("fakes", SIGTERM);
  ASSERT_TRUE(sup.WaitExit("fakes", 60000));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("fakes")), "exited 0");
  for (const char* n : {"server", "standby", "node-1", "node-2"}) {
    EXPECT_NE(std::find(out.begin(), out.end(), fmt::format("[launch] {}: exited 0", n)), out.end())
        << n;
    EXPECT_NE(std::find(out.begin(), out.end(), fmt::format("[{}] stopping {}", n, n)), out.end())
        << n;
  }
  std::filesystem::remove_all(ex.parent_path());
}

TEST(LaunchTest, StartsOnlyNodesInAnExerciseWithoutAServer) {
  std::vector<std::string> out;
  Supervisor sup([&](const std::string&, std::string_view line) { out.emplace_back(line); });
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dt-launch-nosrv" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ex.toml") << "[exercise]\nname = \"fakes\"\nrun_dir = \"" << dir.string()
                                 << "\"\n[auth]\nmode = \"none\"\n[terrain]\n[protocol]\n"
                                    "require_server = false\n"
                                    "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n"
                                    "[[node]]\nname = \"node-2\"\nsite = 1\nhost = 2\n";
  // No server program at all: starting one would fail the launch.
  sup.Start("fakes",
            {DT_LAUNCH, "--config", (dir / "ex.toml").string(), "--node-bin", DT_FAKE_CHILD,
             "--server-bin", "/nonexistent/dt_server", "--ready-timeout-s", "30"});
  ASSERT_TRUE(sup.WaitReady({"fakes"}, 60000));
  EXPECT_NE(std::find(out.begin(), out.end(), "[launch] all 2 processes ready"), out.end());
  sup.Signal("fakes", SIGTERM);
  ASSERT_TRUE(sup.WaitExit("fakes", 60000));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("fakes")), "exited 0");
  for (const char* n : {"node-1", "node-2"}) {
    EXPECT_NE(std::find(out.begin(), out.end(), fmt::format("[launch] {}: exited 0", n)), out.end())
        << n;
  }
  for (const std::string& l : out) EXPECT_EQ(l.find("server"), std::string::npos) << l;
  std::filesystem::remove_all(dir);
}

TEST(LaunchTest, ReportsAChildThatCannotStart) {
  std::vector<std::string> out;
  Supervisor sup([&](const std::string&, std::string_view line) { out.emplace_back(line); });
  const std::filesystem::path ex = WriteExercise("bad");
  sup.Start("fakes", {DT_LAUNCH, "--config", ex.string(), "--node-bin", "/nonexistent/dt_node",
                      "--server-bin", DT_FAKE_CHILD});
  ASSERT_TRUE(sup.WaitExit("fakes", 60000));
  const int st = sup.last_wait_status("fakes");
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 1);  // a child failed (2 is a bad config, 86 a sanitizer report)
  bool named = false;
  for (const std::string& l : out)
    named |= l.find("cannot run /nonexistent/dt_node") != std::string::npos;
  EXPECT_TRUE(named);
  // The servers that did start were stopped, not orphaned.
  EXPECT_NE(std::find(out.begin(), out.end(), "[launch] server: exited 0"), out.end());
  std::filesystem::remove_all(ex.parent_path());
}

TEST(LaunchTest, AChildsConfigErrorExitsTwo) {
  std::vector<std::string> out;
  Supervisor sup([&](const std::string&, std::string_view line) { out.emplace_back(line); });
  const std::filesystem::path ex = WriteExercise("child-cfg");
  // The nodes refuse the exercise as dt_node does a bad scenario: exit 2 before READY.
  const std::filesystem::path node_bin = ex.parent_path() / "bad-config-node.sh";
  std::ofstream(node_bin) << "#!/bin/sh\nexec '" << DT_FAKE_CHILD
                          << "' \"$@\" --mode fail --exit-code 2\n";
  std::filesystem::permissions(node_bin, std::filesystem::perms::owner_all);
  sup.Start("fakes", {DT_LAUNCH, "--config", ex.string(), "--node-bin", node_bin.string(),
                      "--server-bin", DT_FAKE_CHILD});
  ASSERT_TRUE(sup.WaitExit("fakes", 60000));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("fakes")), "exited 2");
  // Every node fails at once; whichever the launcher saw first is named (the others may be
  // stopped by it before their own exit is reaped).
  EXPECT_NE(std::find_if(out.begin(), out.end(),
                         [](const std::string& l) {
                           return l.starts_with("[launch] node-") && l.ends_with(": exited 2");
                         }),
            out.end());
  // The servers were stopped, not orphaned.
  EXPECT_NE(std::find(out.begin(), out.end(), "[launch] server: exited 0"), out.end());
  std::filesystem::remove_all(ex.parent_path());
}

TEST(LaunchTest, BadConfigExitsTwoNamingTheKey) {
  std::vector<std::string> out;
  Supervisor sup([&](const std::string&, std::string_view line) { out.emplace_back(line); });
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("dt-launch-cfg" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ex.toml") << "[exercise]\nname = \"x\"\ntick_hz = -3\n";
  sup.Start("l", {DT_LAUNCH, "--config", (dir / "ex.toml").string()});
  ASSERT_TRUE(sup.WaitExit("l", 60000));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("l")), "exited 2");
  ASSERT_FALSE(out.empty());
  EXPECT_NE(out[0].find("exercise.tick_hz"), std::string::npos) << out[0];
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dt
