// Runs DrillRunner over fake children (test/fake_child.cc) whose control sockets this test serves
// itself, scripted, so the drill's checks see replies chosen to pass or fail them.
#include "launcher/drill_runner.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "launcher/drill_config.h"
#include "runtime/control_server.h"
#include "runtime/exercise_config.h"
#include "runtime/status_report.h"

namespace dt {
namespace {

// A server and one node, their programs fake children that only print READY.
ExerciseConfig FakeExercise(const std::filesystem::path& run_dir) {
  return ParseExerciseConfig(
      fmt::format("[exercise]\nname = \"fakes\"\nrun_dir = \"{}\"\n[auth]\nmode = \"none\"\n"
                  "[terrain]\n[server]\nname = \"server\"\nsite = 1\nhost = 100\n"
                  "[[node]]\nname = \"node-1\"\nsite = 1\nhost = 1\n",
                  run_dir.string()),
      "fakes.toml", run_dir);
}

// Answers every process's control socket, on a thread of its own, in place of dt_server and
// dt_node: all hold one digest and are caught up, and the server holds no feature (nothing a
// node made reached it). A node numbers its creates 1, 2, ... and reports them in own_change_seq;
// its acknowledged_change_seq is 0 in its first status reply (the one the drill asks for right
// after a create) and own_change_seq in every later one.
class ScriptedControl {
 public:
  explicit ScriptedControl(const ExerciseConfig& exercise) {
    for (const ProcessConfig* p : exercise.Processes()) {
      const bool node = p != &*exercise.server;
      auto state = std::make_shared<Process>(
          Process{.name = p->name, .address = p->address, .role = node ? "node" : "server"});
      servers_.push_back(std::make_unique<ControlServer>(
          exercise.SocketPath(p->name),
          [this, state](std::string_view line) { return Answer(*state, line); }));
    }
    thread_ = std::thread([this] {
      while (!stop_) {
        std::vector<pollfd> fds;
        for (const auto& s : servers_) s->AddPollFds(fds);
        ::poll(fds.data(), fds.size(), 50);  // the timeout bounds how long a stop waits
        for (const auto& s : servers_) s->Poll(0);
      }
    });
  }
  ~ScriptedControl() { Stop(); }

  // Stops answering; returns the requests answered, in order, as "<process>: <line>".
  std::vector<std::string> Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    return requests_;
  }

 private:
  struct Process {
    std::string name;
    NodeAddress address;
    std::string role;
    int64_t own_change_seq = 0;
    int status_replies = 0;
  };

  ControlReply Answer(Process& p, std::string_view line) {
    requests_.push_back(fmt::format("{}: {}", p.name, line));
    const std::string_view verb = line.substr(0, line.find(' '));
    if (verb == "status") {
      const int64_t acked = p.status_replies++ == 0 ? 0 : p.own_change_seq;
      return ControlReply::Ok(StatusText(p, acked));
    }
    if (verb == "features") return ControlReply::Ok();
    if (verb == "loss" || verb == "heal") return ControlReply::Ok();
    if (verb == "crater" && p.role == "node") {
      ++p.own_change_seq;
      return ControlReply::Ok(
          FeatureId{p.address.site, p.address.host, static_cast<uint32_t>(p.own_change_seq)}
              .ToString());
    }
    return ControlReply::Fail(fmt::format("the scripted {} does not answer {}", p.name, verb));
  }

  // A status reply as the real processes write it (runtime/status_report.h), so it keeps every
  // key the reader requires: this process's identity and counts, caught up, one digest for all.
  static std::string StatusText(const Process& p, int64_t acked) {
    StatusReport r;
    r.name = p.name;
    r.address = p.address;
    r.role = p.role == "node" ? NodeRole::kNode : NodeRole::kServer;
    r.require_server = true;
    r.signed_on = true;
    r.caught_up = true;
    r.digest = "5eed5eed5eed5eed";
    r.own_feature_number = p.own_change_seq;
    r.own_change_seq = p.own_change_seq;
    r.acknowledged_change_seq = acked;
    return r.ToText();
  }

  std::vector<std::unique_ptr<ControlServer>> servers_;
  std::vector<std::string> requests_;  // the serving thread's until Stop() joins it
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

class DrillRunnerTest : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs the drill (its [drill] table filled in here) to the end; returns Run()'s result and
  // keeps what it printed and what the processes were asked.
  int RunDrill(const std::string& actions) {
    const ExerciseConfig exercise = FakeExercise(dir_);
    DrillConfig drill = ParseDrillConfig(
        "[drill]\nname = \"scripted\"\nexercise = \"fakes.toml\"\ndeadline_s = 60\n"
        "settle_s = 10\nready_timeout_s = 30\n" +
            actions,
        "scripted.toml", dir_);
    DrillOptions options;
    options.programs.node = options.programs.server = DT_FAKE_CHILD;
    DrillRunner runner(std::move(drill), exercise, options);
    // After the runner: it empties run_dir, sockets included.
    ScriptedControl control(exercise);
    testing::internal::CaptureStdout();
    const int result = runner.Run();
    output_ = testing::internal::GetCapturedStdout();
    requests_ = control.Stop();
    return result;
  }

  bool Printed(const std::string& text) const { return output_.find(text) != std::string::npos; }

  const std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() / fmt::format("dt-drill-runner-{}", ::getpid());
  std::string output_;
  std::vector<std::string> requests_;
};

constexpr const char* kCreateOnNode1 =
    "[[action]]\nat_s = 0\ndo = \"command\"\ntargets = \"node-1\"\nline = \"crater 10 20 3\"\n";

TEST_F(DrillRunnerTest, AnAcknowledgedCreateMissingAtTheEndIsLost) {
  // node-1 acknowledges its create in a later status reply, but the server never holds it.
  EXPECT_EQ(RunDrill(kCreateOnNode1), 1) << output_;
  EXPECT_TRUE(Printed("[FAIL] nothing acknowledged lost: 1:1:1\n")) << output_;
  EXPECT_TRUE(Printed("[PASS] crater 10 20 3 on node-1\n")) << output_;
  EXPECT_TRUE(Printed(" ops=1 acknowledged=1 refused=0 unanswered=0 lost=1 ")) << output_;
  // The drill asked node-1 for its sequence right after the create.
  const std::vector<std::string> expected = {"node-1: crater 10 20 3", "node-1: status"};
  ASSERT_GE(requests_.size(), 2u);
  EXPECT_EQ(std::vector<std::string>(requests_.begin(), requests_.begin() + 2), expected);
}

TEST_F(DrillRunnerTest, OnlyTheIssuingIncarnationsAcknowledgementCounts) {
  // The same replies, but node-1 is killed before it acknowledged the create and restarted: the
  // new incarnation's acknowledged_change_seq covers a sequence it reused for a change of its
  // own, so the create is unacknowledged and its absence no loss.
  EXPECT_EQ(RunDrill(std::string(kCreateOnNode1) +
                     "[[action]]\nat_s = 0\ndo = \"kill\"\ntargets = \"node-1\"\n"
                     "[[action]]\nat_s = 0\ndo = \"restart\"\ntargets = \"node-1\"\n"),
            0)
      << output_;
  EXPECT_TRUE(Printed("[PASS] nothing acknowledged lost: 0 acknowledged live features checked\n"))
      << output_;
  EXPECT_TRUE(Printed("[PASS] restart node-1 READY\n")) << output_;
  EXPECT_TRUE(Printed("[drill] summary result=PASS kills=1 restarts=1 ops=1 acknowledged=0 "))
      << output_;
  EXPECT_TRUE(Printed(" lost=0 ")) << output_;
}

}  // namespace
}  // namespace dt
