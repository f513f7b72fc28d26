// Two processes exchange 10 000 PDUs each way over udpm and over DDS inside a private network
// namespace; readiness goes through a pipe, everything is bounded in time, counts are reported.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "log/log.h"
#include "tests/pdu/exchange.h"
#include "transport/test/private_netns.h"

extern char** environ;

namespace dt {
namespace {

constexpr int64_t kCount = 10000;
constexpr int kLimitS = 60;

// Reads from fd until `want` is seen (empty: until EOF), EOF, or the deadline. Returns what was
// read; *eof tells whether the writer closed its end.
std::string ReadUntil(int fd, const std::string& want, std::chrono::steady_clock::time_point end,
                      bool* eof = nullptr) {
  std::string text;
  if (eof) *eof = false;
  while (want.empty() || text.find(want) == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          end - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) break;
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left)) <= 0) break;
    char buf[256];
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n <= 0) {
      if (eof) *eof = (n == 0);
      break;
    }
    text.append(buf, static_cast<size_t>(n));
  }
  return text;
}

void Exchange(const std::string& url) {
  if (auto reason = testing::NetnsSkipReason()) GTEST_SKIP() << *reason;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kLimitS);
  auto transport = MakeTransport(url, exchange::kExercise);

  int ready[2];
  int out[2];
  ASSERT_EQ(pipe2(ready, O_CLOEXEC), 0);
  ASSERT_EQ(pipe2(out, O_CLOEXEC), 0);
  pid_t pid = -1;
  bool peer_ready = false;
  const auto result = exchange::Run(*transport, exchange::kDriver, kCount, deadline, [&] {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, ready[1], 3);  // dup2 clears close-on-exec
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    const std::string count = std::to_string(kCount);
    const std::string limit = std::to_string(kLimitS);
    char* args[] = {const_cast<char*>(DT_EXCHANGE_PEER), const_cast<char*>(url.c_str()),
                    const_cast<char*>(count.c_str()),    const_cast<char*>("3"),
                    const_cast<char*>(limit.c_str()),    nullptr};
    const int rc = posix_spawn(&pid, DT_EXCHANGE_PEER, &actions, nullptr, args, environ);
    posix_spawn_file_actions_destroy(&actions);
    close(ready[1]);
    close(out[1]);
    if (rc != 0) return;
    peer_ready = ReadUntil(ready[0], "ready\n", deadline).find("ready\n") != std::string::npos;
    if (peer_ready) exchange::AwaitPeerReaders(*transport, kLimitS * 1000);
  });
  close(ready[0]);
  ASSERT_GT(pid, 0) << "could not start " << DT_EXCHANGE_PEER;
  // The peer's stdout reaches EOF when it exits; it has its own deadline, so one that is still
  // running well past ours is stuck and is stopped by its PID.
  bool eof = false;
  const std::string peer_line = ReadUntil(out[0], "", deadline + std::chrono::seconds(10), &eof);
  close(out[0]);
  if (!eof) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);

  long long p_sent = -1, p_received = -1, p_dup = -1, p_rejected = -1;
  int p_finished = 0;
  std::sscanf(peer_line.c_str(),
              "sent=%lld received=%lld duplicates=%lld rejected=%lld finished=%d", &p_sent,
              &p_received, &p_dup, &p_rejected, &p_finished);
  std::printf("[%s] driver: %s\n[%s] peer:   %s", url.c_str(), result.ToLine().c_str(), url.c_str(),
              peer_line.c_str());
  ::testing::Test::RecordProperty("driver", result.ToLine());
  ::testing::Test::RecordProperty("peer", peer_line);

  EXPECT_TRUE(peer_ready) << "the peer never signalled readiness";
  EXPECT_TRUE(result.finished);
  EXPECT_EQ(result.sent, kCount);
  EXPECT_EQ(result.received, kCount);
  EXPECT_EQ(result.rejected, 0u);
  EXPECT_EQ(p_sent, kCount);
  EXPECT_EQ(p_received, kCount);
  EXPECT_EQ(p_rejected, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "peer status " << status;
}

TEST(PduExchange, TwoProcessesOverUdpm) { Exchange("udpm://239.255.76.67:7667?ttl=0"); }

TEST(PduExchange, TwoProcessesOverDds) {
  Exchange(std::string("dds://0?config=") + DT_SOURCE_DIR + "/configs/cyclonedds-loopback.xml");
}

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  dt::testing::EnterPrivateNetns(argc, argv);
  dt::log::Init("exchange-driver", "warn");
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
