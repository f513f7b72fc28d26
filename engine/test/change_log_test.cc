// Tests ChangeLog's gap-free point, gaps and replaced slots, the prefix hashes and repair rule of
// anti-entropy, and PlaybackScheduler's pacing and retries.
#include "engine/change_log.h"

#include <vector>

#include <gtest/gtest.h>

#include "engine/change_hash.h"
#include "engine/playback_scheduler.h"
#include "engine/prefix_hashes.h"
#include "engine/repair_rule.h"

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

// Slots are allocated a chunk at a time: a held change stays where it is while thousands more
// arrive, in and out of order, and every one is found where it was put.
TEST(ChangeLogTest, HeldChangesNeverMoveAsTheLogGrows) {
  ChangeLog log;
  ASSERT_TRUE(log.Insert(Numbered(1)));
  const Change* first = log.Find(1);
  std::vector<const Change*> held;
  for (uint32_t s = 2; s <= 5000; s += 2) {
    ASSERT_TRUE(log.Insert(Numbered(s + 1)));  // one ahead, leaving s open
    ASSERT_TRUE(log.Insert(Numbered(s)));
  }
  EXPECT_EQ(log.Find(1), first);
  EXPECT_EQ(log.contiguous(), 5001);
  EXPECT_EQ(log.size(), 5001u);
  for (int64_t s = 1; s <= 5001; ++s) {
    ASSERT_NE(log.Find(s), nullptr) << s;
    EXPECT_EQ(log.Find(s)->stamp.change_seq, s);
    held.push_back(log.Find(s));
  }
  for (uint32_t s = 5002; s <= 6000; ++s) ASSERT_TRUE(log.Insert(Numbered(s)));
  for (int64_t s = 1; s <= 5001; ++s) EXPECT_EQ(log.Find(s), held[static_cast<size_t>(s - 1)]);
  EXPECT_EQ(log.Range(4990, 5010).size(), 21u);
  EXPECT_EQ(log.Find(6001), nullptr);
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

TEST(ChangeLogTest, ReplaceSwapsAHeldSlotInPlaceAndRefusesOneNotHeld) {
  ChangeLog log;
  const auto far = static_cast<uint32_t>(1 + 4 * ChangeLog::kMaxSlotJump);
  for (uint32_t s : {1u, 2u, 3u, far}) ASSERT_TRUE(log.Insert(Numbered(s)));
  const Change* slot = log.Find(2);
  Change other = Numbered(2);
  other.stamp.lamport = 99;
  EXPECT_TRUE(log.Replace(other));
  EXPECT_EQ(log.Find(2), slot);  // the same slot, now holding the other copy
  EXPECT_EQ(*log.Find(2), other);
  Change aside = Numbered(far);
  aside.params = FeatureParams::Crater(20, 20, 3);
  EXPECT_TRUE(log.Replace(aside));
  EXPECT_EQ(*log.Find(far), aside);
  EXPECT_FALSE(log.Replace(Numbered(4)));  // a gap: nothing to replace
  EXPECT_EQ(log.Find(4), nullptr);
  EXPECT_EQ(log.contiguous(), 3);
  EXPECT_EQ(log.size(), 4u);
  EXPECT_EQ(log.max_held(), far);
}

TEST(ChangeLogTest, RemoveTakesAHeldChangeOutAndTheGapFreePointAndMaxHeldFollow) {
  ChangeLog log;
  const auto far = static_cast<uint32_t>(1 + 4 * ChangeLog::kMaxSlotJump);
  for (uint32_t s : {1u, 2u, 3u, 4u, 6u, far}) ASSERT_TRUE(log.Insert(Numbered(s)));
  ASSERT_EQ(log.contiguous(), 4);
  const Change* kept = log.Find(6);
  // The highest change, held aside: max_held falls to the highest still held, in a slot.
  auto removed = log.Remove(far);
  ASSERT_TRUE(removed.has_value());
  EXPECT_EQ(*removed, Numbered(far));
  EXPECT_EQ(log.Find(far), nullptr);
  EXPECT_EQ(log.max_held(), 6);
  EXPECT_EQ(log.size(), 5u);
  // A slot of the gap-free prefix: the gap-free point falls below it, other slots stay put.
  ASSERT_TRUE(log.Remove(3).has_value());
  EXPECT_EQ(log.contiguous(), 2);
  EXPECT_EQ(log.FirstGap(), std::make_pair(int64_t{3}, int64_t{3}));
  EXPECT_EQ(log.Find(6), kept);
  EXPECT_EQ(log.Range(1, 6).size(), 4u);
  // Not held (any more): nothing changes.
  EXPECT_FALSE(log.Remove(3).has_value());
  EXPECT_FALSE(log.Remove(5).has_value());
  EXPECT_EQ(log.size(), 4u);
  // The highest change in a slot, past a gap: max_held skips the empty slot below it.
  ASSERT_TRUE(log.Remove(6).has_value());
  EXPECT_EQ(log.max_held(), 4);
  EXPECT_EQ(log.max_known(), 4);
  // The slot takes a change again, and the gap-free point moves past it as for any arrival.
  EXPECT_TRUE(log.Insert(Numbered(3)));
  EXPECT_EQ(log.contiguous(), 4);
  EXPECT_FALSE(log.has_gap());
  for (uint32_t s : {1u, 2u, 3u, 4u}) ASSERT_TRUE(log.Remove(s).has_value());
  EXPECT_EQ(log.size(), 0u);
  EXPECT_EQ(log.max_held(), 0);
  EXPECT_EQ(log.contiguous(), 0);
}

TEST(PrefixHashesTest, TruncateDropsTheSumsPastAFallenGapFreePoint) {
  ChangeLog log;
  PrefixHashes p;
  for (uint32_t s : {1u, 2u, 3u, 4u}) ASSERT_TRUE(log.Insert(Numbered(s)));
  p.Extend(log);
  const uint64_t two = p.At(2);
  ASSERT_TRUE(log.Remove(3).has_value());
  p.Truncate(log.contiguous());
  EXPECT_EQ(p.length(), 2);
  EXPECT_EQ(p.At(2), two);
  p.Truncate(5);  // beyond what is hashed: nothing changes
  EXPECT_EQ(p.length(), 2);
  // Another copy fills the slot: the sums from it on are of that copy.
  Change other = Numbered(3);
  other.stamp.lamport = 55;
  ASSERT_TRUE(log.Insert(other));
  p.Extend(log);
  EXPECT_EQ(p.length(), 4);
  EXPECT_EQ(p.Range(3, 3), ChangeHash(other));
  EXPECT_EQ(p.Range(4, 4), ChangeHash(Numbered(4)));
}

TEST(PrefixHashesTest, SumsFollowTheGapFreePointAndAReplacedSlot) {
  ChangeLog log;
  PrefixHashes p;
  for (uint32_t s : {1u, 2u, 4u}) ASSERT_TRUE(log.Insert(Numbered(s)));
  p.Extend(log);
  EXPECT_EQ(p.length(), 2);  // 4 is past a gap
  EXPECT_EQ(p.At(0), 0u);
  EXPECT_EQ(p.At(2), ChangeHash(Numbered(1)) + ChangeHash(Numbered(2)));
  ASSERT_TRUE(log.Insert(Numbered(3)));
  p.Extend(log);
  EXPECT_EQ(p.length(), 4);
  EXPECT_EQ(p.Range(3, 4), ChangeHash(Numbered(3)) + ChangeHash(Numbered(4)));
  // Another log holding the same changes, received in another order, sums the same.
  ChangeLog again;
  PrefixHashes q;
  for (uint32_t s : {4u, 2u, 3u, 1u}) ASSERT_TRUE(again.Insert(Numbered(s)));
  q.Extend(again);
  EXPECT_EQ(q.At(4), p.At(4));
  // A different change in slot 2 changes every prefix from 2 on, and only those.
  Change other = Numbered(2);
  other.stamp.lamport = 77;
  ASSERT_TRUE(again.Replace(other));
  q.Replace(2, ChangeHash(Numbered(2)), ChangeHash(other));
  EXPECT_EQ(q.At(1), p.At(1));
  EXPECT_NE(q.At(2), p.At(2));
  EXPECT_EQ(q.Range(3, 4), p.Range(3, 4));
  PrefixHashes fresh;
  fresh.Extend(again);
  EXPECT_EQ(fresh.At(4), q.At(4));
  // The same content in another slot hashes differently: the stamp is part of the bytes.
  Change moved = Numbered(3);
  moved.stamp.change_seq = 2;
  EXPECT_NE(ChangeHash(moved), ChangeHash(Numbered(3)));
}

// Copies of a ditch or area that differ only in a point must hash apart, or anti-entropy would
// take them for the same change.
TEST(ChangeHashTest, EveryPointOfALineOrAreaIsHashed) {
  Change a = Numbered(6);
  a.params = FeatureParams::Ditch({{10, 10, 2, 6}, {40, 12, 2, 6}, {60, 30, 2, 6}}, 1.5);
  Change b = a;
  b.params.points[2].width_m = 6.5;
  EXPECT_NE(ChangeHash(a), ChangeHash(b));
  EXPECT_EQ(CanonicalChangeBytes(a).size(), 107u + 2u + 3u * 32u);
  Change area = Numbered(7);
  area.params =
      FeatureParams::Area({{10, 10, 0, 0}, {30, 10, 0, 0}, {20, 30, 0, 0}}, Material::kWater, 1);
  Change moved = area;
  moved.params.points[1].z_m = 11;
  EXPECT_NE(ChangeHash(area), ChangeHash(moved));
  // A crater's bytes carry no point list: the earlier layout, unchanged.
  EXPECT_EQ(CanonicalChangeBytes(Numbered(1)).size(), 107u);
}

TEST(RepairRuleTest, TheServerThenAStandbyThenTheAuthorIsTheSlotsAuthority) {
  const NodeAddress author{1, 5}, node{1, 2}, server{1, 100}, server2{1, 102}, standby{1, 101};
  using H = std::vector<SlotHolder>;
  auto authority = [&](const H& holders) { return SlotAuthority(author, holders); };
  const SlotHolder a{author, NodeRole::kNode}, n{node, NodeRole::kNode},
      s{server, NodeRole::kServer}, s2{server2, NodeRole::kServer}, t{standby, NodeRole::kStandby};
  EXPECT_EQ(authority(H{n, a, t, s}), server);  // the server's copy: what it acknowledged
  EXPECT_EQ(authority(H{s2, n, s}), server);    // two servers: the lower address
  EXPECT_EQ(authority(H{n, t, a}), standby);    // no server holds it: what a standby stored
  EXPECT_EQ(authority(H{n, a}), author);        // the author's own
  EXPECT_EQ(authority(H{n}), std::nullopt);     // nobody's: the lower copy wins
  EXPECT_EQ(authority(H{}), std::nullopt);
}

TEST(RepairRuleTest, OfTwoDifferentCopiesExactlyOneIsTheLower) {
  Change a = Numbered(5), b = Numbered(5);
  b.params = FeatureParams::Crater(30, 30, 4);
  EXPECT_NE(LowerCopy(a, b), LowerCopy(b, a));
  EXPECT_EQ(LowerCopy(a, b), ChangeHash(a) < ChangeHash(b));
  EXPECT_FALSE(LowerCopy(a, a));
}

TEST(PlaybackSchedulerTest, PacesRetriesAndMovesToTheNextCandidate) {
  ChangeLog log;
  log.Report({1, 1}, 1000);
  const NodeAddress server{9, 9};
  const std::vector<NodeAddress> candidates = {kAuthor, server};
  PlaybackScheduler s(/*window=*/100, /*max_window=*/100, /*retry_ms=*/50);
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
  s.OnResponse(kAuthor, 1, 100, /*range_held=*/true, 61);
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
