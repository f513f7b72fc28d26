// A DDS writer keeps going while one of its readers is killed: its loop is never held up, a live
// reader gets every PDU in order. Two reader processes (this program re-executed with
// --dds-reader) in a private network namespace; readiness through pipes, bounded in time.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "log/log.h"
#include "pdu/test/sample_pdus.h"
#include "transport/dds_transport.h"
#include "transport/retrying_transport.h"
#include "transport/test/private_netns.h"

extern char** environ;

namespace dt {
namespace {

using Clock = std::chrono::steady_clock;

// A small writer history (16 kB) so a reader that acknowledges nothing fills it within a few
// hundred PDUs, and the usual loopback settings; the lease is the transport's 3 s.
const std::string kUrl =
    std::string("dds://0?config=") + DT_SOURCE_DIR + "/transport/test/cyclonedds-small-whc.xml";
constexpr int64_t kCount = 3000;      // PDUs the writer publishes
constexpr int64_t kBeforeKill = 200;  // of which before the victim is killed
constexpr int kLimitS = 60;

std::vector<uint8_t> UpdateBytes(int64_t seq) {
  auto pdu = sample::Update();
  pdu.sender_seq = seq;
  return EncodePdu(pdu);
}

// Reader mode: takes Updates until kCount arrived or the limit passes, publishing a MaxFeature
// "ping" every loop so the writer has traffic to handle; says "ready" on fd 3 once subscribed
// and "received=<n> in_order=<0|1>" on stdout at the end.
int RunReader() {
  DdsTransport t(ParseDdsUrl(kUrl), sample::kSampleExercise);
  int64_t received = 0;
  bool in_order = true;
  t.Subscribe(PduType::kUpdate, [&](std::span<const uint8_t> bytes) {
    dtpdu::update_t pdu;
    if (DecodePdu(bytes, pdu)) return;
    if (pdu.sender_seq != received + 1) in_order = false;
    ++received;
  });
  if (write(3, "ready\n", 6) != 6) return 1;
  close(3);
  const auto end = Clock::now() + std::chrono::seconds(kLimitS);
  const auto ping = EncodePdu(sample::MaxFeature());
  while (received < kCount && Clock::now() < end) {
    (void)t.Publish(PduType::kMaxFeature, ping);
    if (!t.HandleTimeout(10).ok()) break;
  }
  std::printf("received=%lld in_order=%d\n", static_cast<long long>(received), in_order ? 1 : 0);
  return 0;
}

struct Child {
  pid_t pid = -1;
  int out = -1;  // its stdout
};

// Starts this program in reader mode and waits for its "ready".
Child StartReader() {
  int ready[2];
  int out[2];
  if (pipe2(ready, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0) return {};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, ready[1], 3);  // dup2 clears close-on-exec
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  char self[] = "/proc/self/exe";
  char mode[] = "--dds-reader";
  char* args[] = {self, mode, nullptr};
  Child c;
  const int rc = posix_spawn(&c.pid, self, &actions, nullptr, args, environ);
  posix_spawn_file_actions_destroy(&actions);
  close(ready[1]);
  close(out[1]);
  if (rc != 0) {
    close(ready[0]);
    close(out[0]);
    return {};
  }
  c.out = out[0];
  char buf[8] = {};
  pollfd p{ready[0], POLLIN, 0};
  if (poll(&p, 1, kLimitS * 1000) <= 0 || read(ready[0], buf, sizeof buf) <= 0) {
    kill(c.pid, SIGKILL);
    waitpid(c.pid, nullptr, 0);
    c.pid = -1;
  }
  close(ready[0]);
  return c;
}

// Reads a child's stdout to EOF (or the deadline, then kills it by PID) and reaps it.
std::string Finish(Child& c, Clock::time_point end) {
  std::string text;
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
    pollfd p{c.out, POLLIN, 0};
    if (left <= 0 || poll(&p, 1, static_cast<int>(left)) <= 0) {
      kill(c.pid, SIGKILL);
      break;
    }
    char buf[256];
    const ssize_t n = read(c.out, buf, sizeof buf);
    if (n <= 0) break;
    text.append(buf, static_cast<size_t>(n));
  }
  close(c.out);
  waitpid(c.pid, nullptr, 0);
  c.pid = -1;
  return text;
}

TEST(DdsDeadReader, AWriterNeverWaitsForAKilledReaderAndALiveOneGetsEverything) {
  if (auto reason = testing::NetnsSkipReason()) GTEST_SKIP() << *reason;
  const auto deadline = Clock::now() + std::chrono::seconds(kLimitS);
  auto dds = std::make_unique<DdsTransport>(ParseDdsUrl(kUrl), sample::kSampleExercise);
  DdsTransport* raw = dds.get();
  RetryingTransport writer(std::move(dds));
  int64_t pings = 0;
  writer.Subscribe(PduType::kMaxFeature, [&](std::span<const uint8_t>) { ++pings; });

  Child live = StartReader();
  ASSERT_GT(live.pid, 0) << "the live reader did not start";
  Child victim = StartReader();
  ASSERT_GT(victim.pid, 0) << "the victim reader did not start";
  ASSERT_TRUE(raw->WaitForReaders(PduType::kUpdate, 2, kLimitS * 1000));

  // One loop iteration publishes one PDU and handles whatever arrived, as a replica's tick does.
  // Counted: iterations that handled the live reader's pings while writes were being refused
  // (the writer's loop kept running though the carrier could not take its PDUs).
  int64_t busy_iterations = 0;
  size_t most_queued = 0;
  double slowest_publish_ms = 0;
  auto iterate = [&](int64_t seq) {
    if (seq > 0) {
      const auto t0 = Clock::now();
      const Status s = writer.Publish(PduType::kUpdate, UpdateBytes(seq));
      slowest_publish_ms = std::max(
          slowest_publish_ms, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      EXPECT_TRUE(s.ok()) << seq << ": " << s.error().message;
    }
    const bool refused_before = writer.queued() > 0;
    const int64_t pings_before = pings;
    ASSERT_TRUE(writer.HandleTimeout(seq > 0 ? 0 : RetryingTransport::kRetryIntervalMs).ok());
    most_queued = std::max(most_queued, writer.queued());
    if (refused_before && writer.queued() > 0 && pings > pings_before) ++busy_iterations;
  };
  for (int64_t seq = 1; seq <= kBeforeKill; ++seq) iterate(seq);
  ASSERT_EQ(kill(victim.pid, SIGKILL), 0);
  waitpid(victim.pid, nullptr, 0);
  close(victim.out);
  for (int64_t seq = kBeforeKill + 1; seq <= kCount; ++seq) iterate(seq);
  // Until the victim's lease ends its readers hold the writer's history full; after that the
  // queue drains to the live reader.
  while (writer.queued() > 0 && Clock::now() < deadline) iterate(0);

  const std::string line = Finish(live, deadline + std::chrono::seconds(5));
  long long received = -1;
  int in_order = 0;
  std::sscanf(line.c_str(), "received=%lld in_order=%d", &received, &in_order);
  const auto c = writer.counters();
  std::printf(
      "live reader: %s writer: most_queued=%zu retried=%llu failed_writes=%llu given_up=%llu "
      "busy_iterations=%lld slowest_publish_ms=%.3f\n",
      line.c_str(), most_queued, static_cast<unsigned long long>(c.retried),
      static_cast<unsigned long long>(c.failed_writes), static_cast<unsigned long long>(c.given_up),
      static_cast<long long>(busy_iterations), slowest_publish_ms);
  EXPECT_EQ(received, kCount);
  EXPECT_EQ(in_order, 1);
  EXPECT_EQ(writer.queued(), 0u);
  EXPECT_EQ(c.given_up, 0u);
  // The dead reader did fill the history: writes were refused and retried, not waited for...
  EXPECT_GT(c.failed_writes, 0u);
  EXPECT_GT(c.retried, 0u);
  // ...and meanwhile the loop went on handling traffic. A write that blocked for its reliability
  // max_blocking_time (2 s before) would leave room for one or two such iterations before the
  // 3 s lease ends; a write that returns at once leaves thousands.
  EXPECT_GE(busy_iterations, 20);
}

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--dds-reader") == 0) {
    dt::log::Init("dds-reader", "warn");
    return dt::RunReader();
  }
  dt::testing::EnterPrivateNetns(argc, argv);
  dt::log::Init("dds-writer", "warn");
  if (auto reason = dt::testing::NetnsSkipReason()) {
    std::fprintf(stderr, "network tests skipped: %s\n", reason->c_str());
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
