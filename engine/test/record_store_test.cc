// Tests RecordStore: last writer wins, final tombstones, idempotence, order independence, and
// materialisation of overlapping bridges in feature-ID order.
#include "engine/record_store.h"

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/terrain_digest.h"

namespace dt {
namespace {

HeightGrid Ground() { return HeightGrid(33, 4.0, 10.0f); }

Change Make(ChangeKind kind, FeatureId id, FeatureParams params, NodeAddress by, uint32_t seq,
            uint64_t lamport) {
  Change c;
  c.kind = kind;
  c.id = id;
  c.params = std::move(params);
  c.stamp.changed_by = by;
  c.stamp.change_seq = seq;
  c.stamp.lamport = lamport;
  return c;
}

Change Destruct(FeatureId id, NodeAddress by, uint32_t seq, uint64_t lamport) {
  FeatureParams p;
  p.type = FeatureType::kCrater;
  return Make(ChangeKind::kDestruct, id, p, by, seq, lamport);
}

const FeatureId kId{1, 1, 1};
const NodeAddress kA{1, 1};
const NodeAddress kB{1, 2};

TEST(RecordStoreTest, StaleUpdateIsIgnored) {
  RecordStore s(Ground());
  const auto newer = FeatureParams::Crater(50, 50, 6);
  const auto older = FeatureParams::Crater(60, 60, 3);
  EXPECT_EQ(s.Apply(Make(ChangeKind::kUpdate, kId, newer, kA, 2, 5)),
            RecordStore::Outcome::kApplied);
  EXPECT_EQ(s.Apply(Make(ChangeKind::kConstruct, kId, older, kA, 1, 3)),
            RecordStore::Outcome::kStale);
  ASSERT_NE(s.Find(kId), nullptr);
  EXPECT_EQ(s.Find(kId)->params, newer);
  ASSERT_NE(s.terrain().Find(kId), nullptr);
  EXPECT_EQ(s.terrain().Find(kId)->params(), newer);
}

// CheckPlaceable keeps the feature it made for the record applied next; a record of other
// parameters, another ID or a terrain changed in between gets a feature of its own.
TEST(RecordStoreTest, AFeatureCheckedFirstIsPlacedOnlyWhenItIsTheOneApplied) {
  RecordStore s(Ground());
  const auto checked = FeatureParams::Crater(50, 50, 6);
  const auto other = FeatureParams::Crater(60, 60, 3);
  uint32_t seq = 0;
  auto construct = [&](FeatureId id, const FeatureParams& params) {
    ++seq;
    return s.Apply(Make(ChangeKind::kConstruct, id, params, OriginOf(id), seq, seq));
  };
  // The parameters of the feature the terrain holds under `id`.
  auto placed = [&](FeatureId id) {
    const Feature* f = s.terrain().Find(id);
    return f != nullptr && f->id() == id ? std::optional(f->params()) : std::nullopt;
  };
  const FeatureId second{1, 1, 2}, third{1, 1, 3}, fourth{1, 1, 4}, sixth{1, 1, 6};
  const FeatureId fifth{1, 2, 1};

  // Other parameters applied than checked.
  ASSERT_TRUE(s.CheckPlaceable(kId, checked).ok());
  ASSERT_EQ(construct(kId, other), RecordStore::Outcome::kApplied);
  EXPECT_EQ(placed(kId), other);
  // Another ID applied than checked.
  ASSERT_TRUE(s.CheckPlaceable(second, checked).ok());
  ASSERT_EQ(construct(third, checked), RecordStore::Outcome::kApplied);
  EXPECT_EQ(placed(third), checked);
  // Checked, then the terrain changes (another feature lands) before it is applied.
  ASSERT_TRUE(s.CheckPlaceable(fourth, checked).ok());
  ASSERT_EQ(construct(fifth, other), RecordStore::Outcome::kApplied);
  ASSERT_EQ(construct(fourth, checked), RecordStore::Outcome::kApplied);
  EXPECT_EQ(placed(fourth), checked);
  // The usual way: checked, then applied as it was checked.
  ASSERT_TRUE(s.CheckPlaceable(sixth, checked).ok());
  ASSERT_EQ(construct(sixth, checked), RecordStore::Outcome::kApplied);
  EXPECT_EQ(placed(sixth), checked);
  EXPECT_EQ(s.live_count(), 5u);

  // The same terrain as one made without any check.
  RecordStore fresh(Ground());
  for (const auto& [id, r] : s.all()) {
    ASSERT_EQ(fresh.Apply(Make(ChangeKind::kConstruct, id, r.params, OriginOf(id), id.number, 1)),
              RecordStore::Outcome::kApplied);
  }
  EXPECT_EQ(ComputeDigest(s.terrain()), ComputeDigest(fresh.terrain()));
}

TEST(RecordStoreTest, EqualClocksAreOrderedByTheChangingNode) {
  const auto by_a = FeatureParams::Crater(50, 50, 6);
  const auto by_b = FeatureParams::Crater(70, 70, 4);
  RecordStore one(Ground()), two(Ground());
  ASSERT_EQ(one.Apply(Make(ChangeKind::kUpdate, kId, by_a, kA, 1, 7)),
            RecordStore::Outcome::kApplied);
  ASSERT_EQ(one.Apply(Make(ChangeKind::kUpdate, kId, by_b, kB, 1, 7)),
            RecordStore::Outcome::kApplied);
  ASSERT_EQ(two.Apply(Make(ChangeKind::kUpdate, kId, by_b, kB, 1, 7)),
            RecordStore::Outcome::kApplied);
  ASSERT_EQ(two.Apply(Make(ChangeKind::kUpdate, kId, by_a, kA, 1, 7)),
            RecordStore::Outcome::kStale);
  EXPECT_EQ(one.Find(kId)->params, by_b);  // kB > kA
  EXPECT_EQ(ComputeDigest(one.terrain()), ComputeDigest(two.terrain()));
}

TEST(RecordStoreTest, DestroyBeatsAnUpdateWithALaterClock) {
  RecordStore s(Ground());
  ASSERT_EQ(s.Apply(Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(50, 50, 6), kA, 1, 1)),
            RecordStore::Outcome::kApplied);
  ASSERT_EQ(s.Apply(Destruct(kId, kB, 1, 2)), RecordStore::Outcome::kApplied);
  EXPECT_EQ(s.Apply(Make(ChangeKind::kUpdate, kId, FeatureParams::Crater(40, 40, 5), kA, 2, 99)),
            RecordStore::Outcome::kStale);
  EXPECT_TRUE(s.Find(kId)->destroyed);
  EXPECT_EQ(s.terrain().Find(kId), nullptr);
  EXPECT_EQ(s.live_count(), 0u);
  EXPECT_EQ(ComputeDigest(s.terrain()), ComputeDigest(Ground()));
}

TEST(RecordStoreTest, DestroyArrivingBeforeTheConstructLeavesATombstone) {
  RecordStore s(Ground());
  ASSERT_EQ(s.Apply(Destruct(kId, kB, 1, 2)), RecordStore::Outcome::kApplied);
  EXPECT_EQ(s.Apply(Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(50, 50, 6), kA, 1, 1)),
            RecordStore::Outcome::kStale);
  EXPECT_EQ(s.terrain().feature_count(), 0u);
}

TEST(RecordStoreTest, DuplicatesAreIdempotent) {
  RecordStore s(Ground());
  const Change c = Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(50, 50, 6), kA, 1, 1);
  ASSERT_EQ(s.Apply(c), RecordStore::Outcome::kApplied);
  const auto digest = ComputeDigest(s.terrain());
  EXPECT_EQ(s.Apply(c), RecordStore::Outcome::kStale);
  EXPECT_EQ(ComputeDigest(s.terrain()), digest);
  EXPECT_EQ(s.live_count(), 1u);
}

TEST(RecordStoreTest, EveryOrderOfTheSameChangesGivesTheSameTerrain) {
  const FeatureId other{1, 2, 1};
  std::vector<Change> changes = {
      Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(50, 50, 6), kA, 1, 1),
      Make(ChangeKind::kUpdate, kId, FeatureParams::Crater(52, 50, 7), kB, 1, 3),
      Make(ChangeKind::kConstruct, other, FeatureParams::Berm(30, 30, 0.5, 20, 4, 2), kB, 2, 4),
      Make(ChangeKind::kUpdate, kId, FeatureParams::Crater(58, 50, 5), kA, 2, 5),
      Destruct(other, kA, 3, 6),
  };
  std::vector<size_t> order(changes.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::optional<TerrainDigest> first;
  int permutations = 0;
  do {
    RecordStore s(Ground());
    for (size_t i : order) (void)s.Apply(changes[i]);
    const auto d = ComputeDigest(s.terrain());
    if (!first) first = d;
    EXPECT_EQ(d, *first);
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(permutations, 120);
  RecordStore s(Ground());
  for (const Change& c : changes) (void)s.Apply(c);
  EXPECT_EQ(s.Find(kId)->params, FeatureParams::Crater(58, 50, 5));
  EXPECT_TRUE(s.Find(other)->destroyed);
}

TEST(RecordStoreTest, OverlappingBridgesKeepTheLowerIdPlacedWhateverTheOrder) {
  const FeatureId low{1, 1, 5};
  const FeatureId high{1, 2, 1};
  const auto b1 = FeatureParams::Bridge(40, 60, 0.0, 6, 8, 30, 8, 3, 3);
  const auto b2 = FeatureParams::Bridge(50, 60, 0.0, 6, 8, 30, 8, 3, 3);
  const Change c_low = Make(ChangeKind::kConstruct, low, b1, kA, 1, 1);
  const Change c_high = Make(ChangeKind::kConstruct, high, b2, kB, 1, 1);
  RecordStore one(Ground()), two(Ground());
  (void)one.Apply(c_low);
  (void)one.Apply(c_high);
  (void)two.Apply(c_high);
  (void)two.Apply(c_low);
  for (RecordStore* s : {&one, &two}) {
    EXPECT_TRUE(s->Find(low)->placed);
    EXPECT_FALSE(s->Find(high)->placed);
    EXPECT_EQ(s->live_count(), 2u);
    EXPECT_NE(s->terrain().Find(low), nullptr);
    EXPECT_EQ(s->terrain().Find(high), nullptr);
  }
  EXPECT_EQ(ComputeDigest(one.terrain()), ComputeDigest(two.terrain()));
  // Once the lower one is gone, the kept-but-not-placed one is placed.
  (void)one.Apply(Destruct(low, kB, 2, 9));
  EXPECT_TRUE(one.Find(high)->placed);
  EXPECT_NE(one.terrain().Find(high), nullptr);
  // A command that would overlap a placed bridge is refused.
  EXPECT_FALSE(two.CheckPlaceable({1, 3, 1}, b2).ok());
  EXPECT_TRUE(two.CheckPlaceable({1, 3, 1}, FeatureParams::Crater(20, 20, 3)).ok());
}

// What a store that applied `changes` holds, for comparing a rebuilt store with a fresh one.
void ExpectSameAs(const RecordStore& s, const std::vector<Change>& changes) {
  RecordStore fresh(Ground());
  for (const Change& c : changes) (void)fresh.Apply(c);
  EXPECT_EQ(ComputeDigest(s.terrain()), ComputeDigest(fresh.terrain()));
  EXPECT_EQ(s.live_count(), fresh.live_count());
  ASSERT_EQ(s.all().size(), fresh.all().size());
  for (const auto& [id, r] : fresh.all()) {
    const Record* mine = s.Find(id);
    ASSERT_NE(mine, nullptr) << id.ToString();
    EXPECT_EQ(mine->params, r.params) << id.ToString();
    EXPECT_EQ(mine->version, r.version) << id.ToString();
    EXPECT_EQ(mine->destroyed, r.destroyed) << id.ToString();
    EXPECT_EQ(mine->placed, r.placed) << id.ToString();
  }
}

std::vector<const Change*> Of(FeatureId id, const std::vector<Change>& changes) {
  std::vector<const Change*> out;
  for (const Change& c : changes) {
    if (c.id == id) out.push_back(&c);
  }
  return out;
}

TEST(RecordStoreTest, ARebuiltRecordIsWhatApplyingItsChangesAfreshGives) {
  const FeatureId low{1, 1, 5}, high{1, 2, 1}, crater{1, 1, 6};
  const auto b1 = FeatureParams::Bridge(40, 60, 0.0, 6, 8, 30, 8, 3, 3);
  const auto b2 = FeatureParams::Bridge(50, 60, 0.0, 6, 8, 30, 8, 3, 3);
  std::vector<Change> changes = {
      Make(ChangeKind::kConstruct, low, b1, kA, 1, 1),
      Make(ChangeKind::kConstruct, high, b2, kB, 1, 2),
      Make(ChangeKind::kConstruct, crater, FeatureParams::Crater(90, 90, 5), kA, 2, 3),
      Make(ChangeKind::kUpdate, crater, FeatureParams::Crater(95, 90, 6), kB, 2, 4),
  };
  RecordStore s(Ground());
  for (const Change& c : changes) (void)s.Apply(c);
  ASSERT_FALSE(s.Find(high)->placed);
  // Slot A:1 held the lower bridge; another copy of it destroys that bridge instead (a void's
  // place taken by the real change, or the reverse): the higher bridge is placed now.
  changes[0] = Destruct(low, kA, 1, 1);
  s.Rebuild(low, Of(low, changes));
  ExpectSameAs(s, changes);
  EXPECT_TRUE(s.Find(high)->placed);
  // The winning update of the crater gives way to an older one: last writer wins is undone.
  changes[3] = Make(ChangeKind::kUpdate, crater, FeatureParams::Crater(95, 90, 6), kB, 2, 2);
  s.Rebuild(crater, Of(crater, changes));
  ExpectSameAs(s, changes);
  EXPECT_EQ(s.Find(crater)->params, FeatureParams::Crater(90, 90, 5));
  // A feature no held change mentions any more is gone, as if never seen; its origin's next
  // feature is still taken in.
  changes.erase(changes.begin() + 2, changes.end());
  s.Rebuild(crater, Of(crater, changes));
  ExpectSameAs(s, changes);
  EXPECT_EQ(s.Find(crater), nullptr);
  changes.push_back(
      Make(ChangeKind::kConstruct, {1, 1, 7}, FeatureParams::Crater(20, 20, 3), kA, 3, 5));
  (void)s.Apply(changes.back());
  changes.push_back(
      Make(ChangeKind::kConstruct, {1, 1, 2}, FeatureParams::Crater(20, 90, 3), kA, 4, 6));
  (void)s.Apply(changes.back());
  ExpectSameAs(s, changes);
}

TEST(RecordStoreTest, AFeatureOffTheTerrainIsKeptButNotPlaced) {
  RecordStore s(Ground());
  const auto off = FeatureParams::Crater(126, 126, 10);  // the terrain is [0, 128]^2
  ASSERT_EQ(s.Apply(Make(ChangeKind::kConstruct, kId, off, kA, 1, 1)),
            RecordStore::Outcome::kApplied);
  EXPECT_FALSE(s.Find(kId)->placed);
  EXPECT_EQ(s.live_count(), 1u);
  EXPECT_EQ(ComputeDigest(s.terrain()), ComputeDigest(Ground()));
}

std::set<FeatureId> TakeTouched(RecordStore& s) {
  const std::vector<FeatureId> touched = s.TakeTouched();  // a record may be named twice
  return {touched.begin(), touched.end()};
}

TEST(RecordStoreTest, TrackedTouchesNameEveryRecordWhosePlacementMayHaveChanged) {
  RecordStore s(Ground());
  (void)s.Apply(Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(50, 50, 6), kA, 1, 1));
  EXPECT_TRUE(s.TakeTouched().empty());  // not tracking yet
  s.TrackTouched();
  const FeatureId low{1, 1, 5};
  const FeatureId high{1, 2, 1};
  (void)s.Apply(Make(ChangeKind::kConstruct, high,
                     FeatureParams::Bridge(50, 60, 0.0, 6, 8, 30, 8, 3, 3), kB, 1, 1));
  EXPECT_EQ(TakeTouched(s), std::set<FeatureId>{high});
  // A stale change touches nothing; the lower bridge displaces the higher one: both named.
  EXPECT_EQ(s.Apply(Make(ChangeKind::kConstruct, kId, FeatureParams::Crater(60, 60, 3), kA, 1, 0)),
            RecordStore::Outcome::kStale);
  EXPECT_TRUE(s.TakeTouched().empty());
  (void)s.Apply(Make(ChangeKind::kConstruct, low,
                     FeatureParams::Bridge(40, 60, 0.0, 6, 8, 30, 8, 3, 3), kA, 2, 2));
  EXPECT_EQ(TakeTouched(s), (std::set<FeatureId>{low, high}));
  EXPECT_FALSE(s.Find(high)->placed);
  // Destroyed, and a record rebuilt to nothing: both named.
  (void)s.Apply(Destruct(kId, kA, 3, 3));
  s.Rebuild(low, {});
  EXPECT_EQ(TakeTouched(s), (std::set<FeatureId>{kId, low, high}));
  EXPECT_EQ(s.Find(low), nullptr);
  EXPECT_TRUE(s.Find(high)->placed);
}

}  // namespace
}  // namespace dt
