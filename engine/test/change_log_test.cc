// Tests ChangeLog's gap-free point and gaps, and PlaybackScheduler's pacing and retries.
#include "engine/change_log.h"

#include <gtest/gtest.h>

#include "engine/playback_scheduler.h"

namespace dt {
namespace {

const NodeAddress kAuthor{1, 1};

Change Numbered(uint32_t seq) {
  Change c;
  c.id = {1, 1, seq};
  c.params = FeatureParams::Crater(10, 10, 2);
  c.stamp.changed_by = kAuthor;
  c.stamp.change_seq = seq;
  c.stamp.lamport = seq;
  return c;
}

TEST(ChangeLogTest, GapFreePointFollowsArrivalsInAnyOrder) {
  ChangeLog log;
  EXPECT_TRUE(log.Insert(Numbered(2)));
  EXPECT_EQ(log.contiguous(), 0);
  EXPECT_TRUE(log.has_gap());
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{1}, int64_t{1}));
  EXPECT_TRUE(log.Insert(Numbered(1)));
  EXPECT_EQ(log.contiguous(), 2);
  EXPECT_FALSE(log.Insert(Numbered(2)));  // duplicate
  EXPECT_FALSE(log.has_gap());
  log.Report({1, 1}, 9);
  EXPECT_TRUE(log.Insert(Numbered(6)));
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{3}, int64_t{5}));
  for (uint32_t s : {3u, 4u, 5u}) EXPECT_TRUE(log.Insert(Numbered(s)));
  EXPECT_EQ(log.contiguous(), 6);
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{7}, int64_t{9}));
  EXPECT_EQ(log.Range(2, 4).size(), 3u);
  // A reporter's latest claim counts: an author that lost changes takes its claim back.
  log.Report({1, 1}, 6);
  EXPECT_FALSE(log.has_gap());
  log.Report({9, 9}, 8);
  EXPECT_TRUE(log.has_gap());
  log.ForgetReporter({9, 9});
  EXPECT_FALSE(log.has_gap());
}

TEST(ChangeLogTest, ChangesFarAheadAreHeldAsideAndStillCountInOrder) {
  ChangeLog log;
  const auto far = static_cast<uint32_t>(1 + 4 * ChangeLog::kMaxSlotJump);
  EXPECT_TRUE(log.Insert(Numbered(1)));
  EXPECT_TRUE(log.Insert(Numbered(far)));      // a rejoining node hears a live change first
  EXPECT_TRUE(log.Insert(Numbered(far + 2)));  // and another, past a gap
  EXPECT_FALSE(log.Insert(Numbered(far)));
  EXPECT_EQ(log.max_held(), far + 2);
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{2}, int64_t{far - 1}));
  const Change* held = log.Find(far);
  ASSERT_NE(held, nullptr);
  for (uint32_t s = 2; s < far; ++s) ASSERT_TRUE(log.Insert(Numbered(s)));
  EXPECT_EQ(log.Find(far), held);  // held changes never move
  EXPECT_FALSE(log.Insert(Numbered(far)));
  EXPECT_EQ(log.contiguous(), far);
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{far + 1}, int64_t{far + 1}));
  EXPECT_TRUE(log.Insert(Numbered(far + 1)));
  EXPECT_EQ(log.contiguous(), far + 2);
  EXPECT_EQ(log.size(), size_t{far + 2});
  const auto range = log.Range(far - 1, far + 5);
  ASSERT_EQ(range.size(), 4u);
  for (size_t i = 0; i < range.size(); ++i) {
    EXPECT_EQ(range[i]->stamp.change_seq, far - 1 + i);
  }
  EXPECT_EQ(log.Range(1, far + 2).size(), size_t{far + 2});
}

TEST(PlaybackSchedulerTest, PacesRetriesAndMovesToTheNextCandidate) {
  ChangeLog log;
  log.Report({1, 1}, 1000);
  const NodeAddress server{9, 9};
  const std::vector<NodeAddress> candidates = {kAuthor, server};
  PlaybackScheduler s(/*window=*/100, /*retry_ms=*/50);
  auto r = s.Poll(kAuthor, log, candidates, 0);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->start, 1);
  EXPECT_EQ(r->end, 100);  // at most a window
  EXPECT_EQ(r->target, kAuthor);
  EXPECT_FALSE(s.Poll(kAuthor, log, candidates, 10).has_value());  // outstanding
  // No answer within the retry period: the same range, from the server.
  r = s.Poll(kAuthor, log, candidates, 60);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->start, 1);
  EXPECT_EQ(r->target, server);
  // The range arrives and its marker too: the next window is asked at once, from the author.
  for (uint32_t i = 1; i <= 100; ++i) ASSERT_TRUE(log.Insert(Numbered(i)));
  s.OnResponse(kAuthor, 1, 100);
  r = s.Poll(kAuthor, log, candidates, 61);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->start, 101);
  EXPECT_EQ(r->end, 200);
  EXPECT_EQ(r->target, kAuthor);
  for (uint32_t i = 101; i <= 1000; ++i) ASSERT_TRUE(log.Insert(Numbered(i)));
  EXPECT_FALSE(s.Poll(kAuthor, log, candidates, 62).has_value());
  EXPECT_TRUE(s.idle());
}

}  // namespace
}  // namespace dt
