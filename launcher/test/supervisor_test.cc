#include "launcher/supervisor.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace dt {
namespace {

std::vector<std::string> Fake(const std::string& name, const std::string& mode,
                              int exit_code = -1) {
  std::vector<std::string> argv = {DT_FAKE_CHILD, "--name", name, "--mode", mode};
  if (exit_code >= 0) {
    argv.push_back("--exit-code");
    argv.push_back(std::to_string(exit_code));
  }
  return argv;
}

class SupervisorTest : public ::testing::Test {
 protected:
  Supervisor sup{[this](const std::string& name, std::string_view line) {
    lines[name].emplace_back(line);
    if (on_line) on_line(line);
  }};
  std::map<std::string, std::vector<std::string>> lines;
  std::function<void(std::string_view)> on_line;
};

// The PID a wrapper-mode fake child printed for its descendant.
pid_t DescendantOf(const std::vector<std::string>& child_lines) {
  for (const std::string& l : child_lines) {
    if (l.rfind("descendant ", 0) == 0) return static_cast<pid_t>(std::stoi(l.substr(11)));
  }
  return -1;
}

// Waits up to timeout_ms for a process to end (a pidfd becomes readable), then reaps it: this
// test is the orphan's subreaper. Returns its wait status, or -1 if it is still running.
int WaitForEnd(pid_t pid, int timeout_ms) {
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  if (pidfd < 0) return -1;
  pollfd p{pidfd, POLLIN, 0};
  const int ready = poll(&p, 1, timeout_ms);
  close(pidfd);
  if (ready != 1) return -1;
  int status = 0;
  return waitpid(pid, &status, 0) == pid ? status : -1;
}

// Orphaned descendants of the fake children become this process's children, to be reaped. The
// alarm ends the test binary ("Alarm clock") if a stop hangs, as it did while a descendant
// holding the pipe kept a dead child "running".
class Subreaper {
 public:
  Subreaper() {
    prctl(PR_SET_CHILD_SUBREAPER, 1);
    alarm(60);
  }
  ~Subreaper() {
    alarm(0);
    prctl(PR_SET_CHILD_SUBREAPER, 0);
  }
};

TEST_F(SupervisorTest, WaitsForEveryReadyAndStopsCleanly) {
  for (const char* n : {"server", "node-1", "node-2"}) sup.Start(n, Fake(n, "ready"));
  ASSERT_TRUE(sup.WaitReady({"server", "node-1", "node-2"}, 10000));
  EXPECT_TRUE(sup.ready("node-1"));
  EXPECT_EQ(lines["node-1"][0], "starting node-1");
  // stderr arrives too, and a line written in two pieces stays one line.
  bool saw_stderr = false;
  for (const std::string& l : lines["node-2"]) saw_stderr |= (l == "half a line from stderr");
  EXPECT_TRUE(saw_stderr);
  sup.StopAll(5000);
  for (const char* n : {"server", "node-1", "node-2"}) {
    EXPECT_FALSE(sup.running(n));
    EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status(n)), "exited 0") << n;
    EXPECT_EQ(lines[n].back(), std::string("stopping ") + n);  // nothing lost at exit
  }
}

TEST_F(SupervisorTest, ChildExitingBeforeReadyIsNamed) {
  sup.Start("node-1", Fake("node-1", "ready"));
  sup.Start("node-2", Fake("node-2", "fail", 3));
  Status s = sup.WaitReady({"node-1", "node-2"}, 10000);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("node-2 exited 3 before it was ready"), std::string::npos)
      << s.error().message;
  sup.StopAll(5000);
}

TEST_F(SupervisorTest, TimeoutNamesTheSilentOnes) {
  sup.Start("a", Fake("a", "ready"));
  sup.Start("b", Fake("b", "silent"));
  Status s = sup.WaitReady({"a", "b"}, 300);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("not ready after 300 ms: b"), std::string::npos)
      << s.error().message;
  sup.StopAll(5000);
}

TEST_F(SupervisorTest, TimeoutQuotesWhatTheChildSaidAboutItsClock) {
  const std::string clock_line =
      "2026-01-02T03:04:05.678 warning [b] clock skew: every PDU received is stamped about 45 s "
      "behind this host's clock: this host's clock is probably 45 s ahead of the exercise";
  const std::string drop_line =
      "2026-01-02T03:04:05.679 warning [b] dropped a Construct PDU: stale (sent by 1:1 45.000 s "
      "before this host's clock (tolerance 30.000 s)); 3 more stale since the last such line";
  const std::string info_line = "2026-01-02T03:04:05.680 info [b] signing on";
  std::vector<std::string> b = Fake("b", "silent");
  b.insert(b.end(), {"--say", clock_line, "--say", drop_line, "--say", info_line});
  std::vector<std::string> c = Fake("c", "silent");
  c.insert(c.end(), {"--say", drop_line, "--say", info_line});
  sup.Start("a", Fake("a", "ready"));
  sup.Start("b", b);
  sup.Start("c", c);
  sup.Start("d", Fake("d", "silent"));
  // Every line is read before the wait runs out: stderr's, then "said" on stdout.
  const auto said = [&](const char* n) { return !lines[n].empty() && lines[n].back() == "said"; };
  for (int i = 0; i < 100 && !(said("b") && said("c") && sup.ready("a")); ++i) sup.Poll(100);
  ASSERT_TRUE(said("b") && said("c"));
  Status s = sup.WaitReady({"a", "b", "c", "d"}, 1);
  ASSERT_FALSE(s);
  // b's clock line outranks its later warning; c, with no clock line, has its latest warning; d
  // said nothing.
  EXPECT_EQ(s.error().message, "not ready after 1 ms: b (its last word: \"" + clock_line +
                                   "\"), c (its last word: \"" + drop_line + "\"), d");
  // A restart forgets what the last run said.
  sup.StopAll(5000);
  sup.Start("b", Fake("b", "silent"));
  EXPECT_EQ(sup.last_word("b"), "");
  sup.StopAll(5000);
}

TEST_F(SupervisorTest, EscalatesToSigkillAndRestartsUnderTheSameName) {
  sup.Start("stubborn", Fake("stubborn", "ignore-term"));
  ASSERT_TRUE(sup.WaitReady({"stubborn"}, 10000));
  sup.StopAll(200);
  const int st = sup.last_wait_status("stubborn");
  ASSERT_TRUE(WIFSIGNALED(st));
  EXPECT_EQ(WTERMSIG(st), SIGKILL);

  sup.Start("stubborn", Fake("stubborn", "ready", 5));
  EXPECT_FALSE(sup.ready("stubborn"));  // READY counts per start
  ASSERT_TRUE(sup.WaitReady({"stubborn"}, 10000));
  EXPECT_THROW(sup.Start("stubborn", Fake("stubborn", "ready")), std::runtime_error);
  sup.Signal("stubborn", SIGKILL);
  EXPECT_TRUE(sup.WaitExit("stubborn", 10000));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("stubborn")), "killed by signal 9 (Killed)");
  EXPECT_EQ(sup.names().size(), 1u);
}

// A child started through a wrapper that forks: stopping it stops the whole group.
TEST_F(SupervisorTest, StoppingAChildStopsWhatItStarted) {
  Subreaper subreaper;
  sup.Start("node-1", Fake("node-1", "wrapper"));
  ASSERT_TRUE(sup.WaitReady({"node-1"}, 10000));
  const pid_t descendant = DescendantOf(lines["node-1"]);
  ASSERT_GT(descendant, 0);
  sup.StopAll(5000);
  EXPECT_FALSE(sup.running("node-1"));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("node-1")), "exited 0");
  EXPECT_EQ(lines["node-1"].back(), "stopping node-1");
  const int st = WaitForEnd(descendant, 5000);
  ASSERT_NE(st, -1) << "the descendant outlived the stop";
  // SIGTERM with the child, or SIGKILL when the child's exit is seen first.
  EXPECT_TRUE(WIFSIGNALED(st) && (WTERMSIG(st) == SIGTERM || WTERMSIG(st) == SIGKILL))
      << DescribeWaitStatus(st);
}

// A descendant in a group of its own keeps the output pipe open after the child has exited:
// the child still counts as exited, with every line it wrote.
TEST_F(SupervisorTest, AnExitedChildIsNotKeptRunningByWhoHoldsItsPipe) {
  Subreaper subreaper;
  sup.Start("node-1", Fake("node-1", "escaping-wrapper"));
  ASSERT_TRUE(sup.WaitReady({"node-1"}, 10000));
  const pid_t descendant = DescendantOf(lines["node-1"]);
  ASSERT_GT(descendant, 0);
  sup.Signal("node-1", SIGTERM);
  EXPECT_TRUE(sup.WaitExit("node-1", 10000));
  EXPECT_FALSE(sup.running("node-1"));
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("node-1")), "exited 0");
  EXPECT_EQ(lines["node-1"].back(), "stopping node-1");
  ASSERT_EQ(kill(descendant, SIGKILL), 0);
  EXPECT_NE(WaitForEnd(descendant, 5000), -1);
}

// Ctrl-C starts the stop; a second Ctrl-C during the grace period kills at once.
TEST_F(SupervisorTest, ASecondStopSignalKillsAtOnce) {
  int wake[2];
  ASSERT_EQ(pipe2(wake, O_NONBLOCK | O_CLOEXEC), 0);
  sup.set_wake_fd(wake[0]);
  sup.Start("stubborn", Fake("stubborn", "ignore-term"));
  ASSERT_TRUE(sup.WaitReady({"stubborn"}, 10000));
  ASSERT_EQ(write(wake[1], "s", 1), 1);  // the first stop signal, as dt_launch sees it
  ASSERT_TRUE(sup.Poll(0));
  on_line = [&](std::string_view line) {
    if (line == "ignoring SIGTERM") {
      ASSERT_EQ(write(wake[1], "s", 1), 1);  // the second stop signal
    }
  };
  sup.StopAll(60000);
  EXPECT_EQ(DescribeWaitStatus(sup.last_wait_status("stubborn")), "killed by signal 9 (Killed)");
  EXPECT_EQ(lines["stubborn"].back(), "(another stop signal during the stop: sent SIGKILL)");
  close(wake[0]);
  close(wake[1]);
}

TEST_F(SupervisorTest, MissingProgramFailsAtStart) {
  try {
    sup.Start("ghost", {"/nonexistent/dt_ghost"});
    FAIL() << "expected a throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ghost: cannot run /nonexistent/dt_ghost"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(sup.running("ghost"));
}

}  // namespace
}  // namespace dt
