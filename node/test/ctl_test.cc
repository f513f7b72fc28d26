// Runs dt_ctl itself against a control socket served here by the real command parser, so what
// reaches the socket, what dt_ctl prints and how it exits are those of the program a user runs.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "runtime/control_command.h"
#include "runtime/control_server.h"
#include "runtime/test/map_actions.h"

extern char** environ;

namespace dt {
namespace {

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

struct CtlRun {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::vector<std::string> lines;  // the requests the socket received
};

class CtlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / fmt::format("dt-ctl-test-{}", ::getpid());
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "ex.toml")
        << "[exercise]\nname = \"ctl\"\nrun_dir = \"" << dir_.string()
        << "\"\n[auth]\nmode = \"none\"\n[terrain]\n[server]\nname = \"server\"\nsite = 1\n"
           "host = 100\n[[node]]\nname = \"node-1\"\nsite = 1\n"
           "host = 1\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs `dt_ctl --name node-1 <words>` while serving node-1's socket; returns once it exited.
  CtlRun Run(const std::vector<std::string>& words) {
    CtlRun run;
    ControlServer server(dir_ / "node-1.sock", [&](std::string_view line) {
      run.lines.emplace_back(line);
      Result<ControlCommand> c = ParseControlCommand(line);
      if (!c) return ControlReply::Fail(c.error().message);
      return RunFeatureCommand(c.value(), node_);
    });
    std::vector<std::string> args = {DT_CTL, "--config", (dir_ / "ex.toml").string(), "--name",
                                     "node-1"};
    args.insert(args.end(), words.begin(), words.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string out_path = (dir_ / "out").string(), err_path = (dir_ / "err").string();
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&files, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, DT_CTL, &files, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&files);
    if (spawned != 0) {
      ADD_FAILURE() << "cannot run " << DT_CTL;
      return run;
    }
    // Serve until dt_ctl exits: its pidfd becomes readable then. The deadline only bounds a hang.
    const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    bool exited = false;
    while (pidfd >= 0 && !exited) {
      const auto left_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                               deadline - std::chrono::steady_clock::now())
                               .count();
      if (left_ms <= 0) break;
      std::vector<pollfd> fds = {{pidfd, POLLIN, 0}};
      server.AddPollFds(fds);
      ::poll(fds.data(), fds.size(), static_cast<int>(left_ms));
      server.Poll(0);
      exited = (fds[0].revents & POLLIN) != 0;
    }
    if (!exited) {
      ADD_FAILURE() << "dt_ctl did not exit within 30 s";
      ::kill(pid, SIGKILL);
    }
    if (pidfd >= 0) ::close(pidfd);
    int status = 0;
    ::waitpid(pid, &status, 0);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = ReadFile(out_path);
    run.err = ReadFile(err_path);
    return run;
  }

  std::filesystem::path dir_;
  MapActions node_;
};

TEST_F(CtlTest, NegativeNumbersReachTheCommandAsArguments) {
  CtlRun r = Run({"drive", "0", "-1e3", "-.5"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.lines, std::vector<std::string>{"drive 0 -1e3 -.5"});
  ASSERT_EQ(node_.drives.size(), 1u);
  EXPECT_EQ(node_.drives[0].speed_mps, -1000.0);
  EXPECT_DOUBLE_EQ(node_.drives[0].rate, -0.5 * std::numbers::pi / 180.0);

  r = Run({"berm", "50", "50", "-90", "20", "4", "2"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(node_.features.size(), 1u);
  EXPECT_DOUBLE_EQ(node_.features.begin()->second.direction_rad, -std::numbers::pi / 2);
}

TEST_F(CtlTest, InfinitiesReachTheParserWhichRefusesThem) {
  CtlRun r = Run({"drive", "0", "-inf", "0"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.lines, std::vector<std::string>{"drive 0 -inf 0"});
  EXPECT_EQ(r.err, "error: speed_mps \"-inf\" is not a finite number\n");
  r = Run({"crater", "50", "50", "-nan"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, "error: radius_m \"-nan\" is not a finite number\n");
  EXPECT_TRUE(node_.drives.empty());
  EXPECT_TRUE(node_.features.empty());
}

TEST_F(CtlTest, AClampedSpeedIsReported) {
  const CtlRun r = Run({"drive", "0", "1e30", "0"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, fmt::format("speed 1e+30 m/s clamped to {} m/s, the tank's top speed\n",
                               TankType().max_speed_mps));
}

}  // namespace
}  // namespace dt
