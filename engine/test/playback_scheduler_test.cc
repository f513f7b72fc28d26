// Tests PlaybackScheduler's window: grown by answers that waited on a long round trip, bounded,
// kept at its base when the round trip hides inside a tick, halved when a range is asked again.
#include "engine/playback_scheduler.h"

#include <vector>

#include <gtest/gtest.h>

#include "engine/change_log.h"

namespace dt {
namespace {

const NodeAddress kAuthor{1, 1};
const std::vector<NodeAddress> kCandidates = {kAuthor};
constexpr int64_t kTickMs = 10;
constexpr int64_t kRetryMs = 300;

Change Numbered(int64_t seq) {
  Change c;
  c.id = {1, 1, static_cast<uint32_t>(seq)};
  c.params = FeatureParams::Crater(10, 10, 2);
  c.stamp.changed_by = kAuthor;
  c.stamp.change_seq = static_cast<uint32_t>(seq);
  c.stamp.lamport = static_cast<uint64_t>(seq);
  return c;
}

// A log missing 10^5 of the author's changes and a scheduler ticking every 10 ms.
class WindowTest : public ::testing::Test {
 protected:
  WindowTest() : scheduler_(64, 1024, kRetryMs) {
    log_.Report(kAuthor, 100000);
    Tick();
    Tick();
  }
  void Tick() { scheduler_.OnTick((now_ms_ += kTickMs)); }

  // Sends the next request, lets its answer start `latency_ms` later and take `transfer_ms` to
  // arrive whole with its marker; returns how many changes it asked for.
  int64_t Round(int64_t latency_ms, int64_t transfer_ms) {
    auto r = scheduler_.Poll(kAuthor, log_, kCandidates, now_ms_);
    EXPECT_TRUE(r.has_value());
    if (!r) return 0;
    for (int64_t t = 0; t < latency_ms; t += kTickMs) Tick();
    scheduler_.OnArrival(kAuthor, r->start, now_ms_);
    for (int64_t t = 0; t < transfer_ms; t += kTickMs) Tick();
    for (int64_t s = r->start; s <= r->end; ++s) EXPECT_TRUE(log_.Insert(Numbered(s)));
    scheduler_.OnResponse(kAuthor, r->start, r->end, /*range_held=*/true, now_ms_);
    return r->end - r->start + 1;
  }

  ChangeLog log_;
  PlaybackScheduler scheduler_;
  int64_t now_ms_ = 0;
};

TEST_F(WindowTest, ALongRoundTripDoublesTheWindowUpToItsBound) {
  std::vector<int64_t> sizes;
  for (int i = 0; i < 7; ++i) sizes.push_back(Round(100, 0));
  EXPECT_EQ(sizes, (std::vector<int64_t>{64, 128, 256, 512, 1024, 1024, 1024}));
}

TEST_F(WindowTest, ARoundTripWithinATickKeepsTheBaseWindow) {
  for (int i = 0; i < 10; ++i) EXPECT_EQ(Round(i % 2 == 0 ? 0 : kTickMs, 0), 64);
  // Grown on a long round trip, it falls back by halves once the round trips are short.
  for (int i = 0; i < 3; ++i) Round(100, 0);
  EXPECT_EQ(scheduler_.window(kAuthor), 512);
  EXPECT_EQ(Round(0, 0), 512);
  EXPECT_EQ(Round(0, 0), 256);
  EXPECT_EQ(Round(0, 0), 128);
  EXPECT_EQ(Round(0, 0), 64);
  EXPECT_EQ(scheduler_.window(kAuthor), 64);
}

TEST_F(WindowTest, TheWindowIsWhatArrivesInFourLatenciesAndWithinHalfTheRetryTime) {
  // 64 changes in 40 ms, 110 ms after the request (100 beyond a tick): 1.6 changes per ms; four
  // latencies' worth (640) is beyond what arrives within half the retry time (240).
  std::vector<int64_t> sizes;
  for (int i = 0; i < 5; ++i) {
    const int64_t w = scheduler_.window(kAuthor);
    sizes.push_back(Round(110, w * 40 / 64));
  }
  EXPECT_EQ(sizes, (std::vector<int64_t>{64, 128, 240, 240, 240}));
}

TEST_F(WindowTest, ARangeAskedForAgainHalvesTheWindow) {
  for (int i = 0; i < 4; ++i) Round(100, 0);
  ASSERT_EQ(scheduler_.window(kAuthor), 1024);
  auto r = scheduler_.Poll(kAuthor, log_, kCandidates, now_ms_);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->end - r->start + 1, 1024);
  // Nothing comes back within the retry time: asked again, half as much.
  for (int64_t t = 0; t <= kRetryMs; t += kTickMs) Tick();
  r = scheduler_.Poll(kAuthor, log_, kCandidates, now_ms_);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->end - r->start + 1, 512);
  EXPECT_EQ(scheduler_.attempts(kAuthor), 1u);
}

TEST(PlaybackSchedulerFixedTest, AMaxWindowNotAboveTheWindowKeepsItFixed) {
  ChangeLog log;
  log.Report(kAuthor, 100000);
  PlaybackScheduler s(64, 0, kRetryMs);
  int64_t now = 0;
  s.OnTick(now);
  s.OnTick(now += kTickMs);
  for (int i = 0; i < 4; ++i) {
    auto r = s.Poll(kAuthor, log, kCandidates, now);
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->end - r->start + 1, 64);
    s.OnArrival(kAuthor, r->start, now += 100);
    for (int64_t q = r->start; q <= r->end; ++q) ASSERT_TRUE(log.Insert(Numbered(q)));
    s.OnResponse(kAuthor, r->start, r->end, true, now);
  }
}

}  // namespace
}  // namespace dt
