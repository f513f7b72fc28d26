#include "launcher/supervisor.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

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
  Supervisor sup{
      [this](const std::string& name, std::string_view line) { lines[name].emplace_back(line); }};
  std::map<std::string, std::vector<std::string>> lines;
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
