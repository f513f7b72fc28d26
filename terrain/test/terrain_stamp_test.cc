// Tests of the terrain's stamps: AreaStamp per area, the change log, stamps drawn per thread.
#include <cstdint>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "terrain/terrain.h"
#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

using test::SlopedGround;

FeatureId Id(uint32_t n) { return {1, 1, n}; }

// AreaStamp moves for the squares a change can alter and for no other: a feature's squares when it
// is added, replaced or removed; the squares around a post that moved and every square of the
// features draped on them; a square whose soil changed.
TEST(TerrainAreaStamp, MovesOnlyWhereAChangeCanAlterAnAnswer) {
  Terrain t(SlopedGround());  // 2 m squares
  const Rect here{50.0, 50.0, 51.0, 51.0}, far{150.0, 150.0, 151.0, 151.0};
  const Rect crater_edge{59.0, 50.0, 59.5, 50.5};  // inside the crater's bounds, off its centre
  uint64_t seen = t.stamp();
  EXPECT_LE(t.AreaStamp(here), seen);
  auto moved = [&](const Rect& r) { return t.AreaStamp(r) > seen; };

  ASSERT_TRUE(t.Add(Id(1), FeatureParams::Crater(55.0, 50.0, 5.0)).ok());
  EXPECT_TRUE(moved(here));
  EXPECT_TRUE(moved(crater_edge));
  EXPECT_FALSE(moved(far));
  EXPECT_LE(t.AreaStamp(here), t.stamp());

  seen = t.stamp();
  ASSERT_TRUE(t.Update(Id(1), FeatureParams::Crater(55.0, 50.0, 4.0)).ok());
  EXPECT_TRUE(moved(crater_edge));  // in the old bounds only
  EXPECT_FALSE(moved(far));

  seen = t.stamp();
  ASSERT_TRUE(t.Remove(Id(1)).ok());
  EXPECT_TRUE(moved(here));
  EXPECT_FALSE(moved(far));

  // A post far from the crater's centre moves: the crater drapes over its squares, so all of the
  // crater's squares change; a square beyond it does not.
  ASSERT_TRUE(t.Add(Id(2), FeatureParams::Crater(55.0, 50.0, 5.0)).ok());
  seen = t.stamp();
  ASSERT_TRUE(t.SetPostElevation(30, 25, 20.0f).ok());  // x 60 m, z 50 m: under the rim
  EXPECT_TRUE(moved(Rect{59.0, 49.0, 59.5, 49.5}));
  EXPECT_TRUE(moved(Rect{50.5, 50.5, 50.6, 50.6}));  // the crater's far side
  EXPECT_FALSE(moved(Rect{80.0, 50.0, 81.0, 51.0}));

  seen = t.stamp();
  ASSERT_TRUE(t.SetSoil({75, 75}, TriangleHalf::kLower, Material::kMud).ok());
  EXPECT_TRUE(moved(Rect{150.5, 150.5, 151.0, 151.0}));
  EXPECT_FALSE(moved(here));

  seen = t.stamp();
  t.RemoveAll();
  EXPECT_TRUE(moved(far));
  EXPECT_TRUE(moved(here));
}

// The change log names the squares each change touched, after a stamp the caller saw: a crater's
// squares when it is added and removed, the squares around a moved post; and says when it no
// longer holds every change since (overflow, RemoveAll).
TEST(TerrainChangeLog, NamesTheAreasChangedSinceAStamp) {
  Terrain t(SlopedGround());  // 2 m squares
  const Rect far{150.0, 150.0, 151.0, 151.0};
  uint64_t seen = t.stamp();
  ASSERT_TRUE(t.ChangedAreasSince(seen).has_value());
  EXPECT_TRUE(t.ChangedAreasSince(seen)->empty());

  ASSERT_TRUE(t.Add(Id(1), FeatureParams::Crater(55.0, 51.0, 5.0)).ok());
  auto areas = t.ChangedAreasSince(seen);
  ASSERT_TRUE(areas.has_value());
  ASSERT_EQ(areas->size(), 1u);
  const Rect b = t.Find(Id(1))->Bounds();
  const Rect a = areas->front();
  // The squares the bounds touch: whole squares holding the bounds, less than a square larger.
  EXPECT_LE(a.min_x, b.min_x);
  EXPECT_GE(a.min_x, b.min_x - 2.0);
  EXPECT_GE(a.max_x, b.max_x);
  EXPECT_LE(a.max_x, b.max_x + 2.0);  // a bound on a square's edge takes the square beyond
  EXPECT_LE(a.min_z, b.min_z);
  EXPECT_GE(a.max_z, b.max_z);
  EXPECT_FALSE(a.Intersects(far));

  seen = t.stamp();
  ASSERT_TRUE(t.SetPostElevation(75, 75, 3.0f).ok());  // x 150, z 150: away from the crater
  areas = t.ChangedAreasSince(seen);
  ASSERT_TRUE(areas.has_value());
  ASSERT_EQ(areas->size(), 1u);
  EXPECT_TRUE(areas->front().Intersects(far));
  EXPECT_FALSE(areas->front().Intersects(b));

  seen = t.stamp();
  ASSERT_TRUE(t.Remove(Id(1)).ok());
  areas = t.ChangedAreasSince(seen);
  ASSERT_TRUE(areas.has_value());
  ASSERT_EQ(areas->size(), 1u);
  EXPECT_TRUE(areas->front().Intersects(b));

  // Older than the log holds: nullopt, not a partial list.
  seen = t.stamp();
  for (size_t k = 0; k <= Terrain::kChangeLogEntries; ++k) {
    ASSERT_TRUE(t.SetSoil({static_cast<int>(k % 90), static_cast<int>(k / 90)},
                          TriangleHalf::kLower, k % 2 ? Material::kMud : Material::kSand)
                    .ok());
  }
  EXPECT_FALSE(t.ChangedAreasSince(seen).has_value());
  seen = t.stamp();
  EXPECT_TRUE(t.ChangedAreasSince(seen).has_value());
  // The log has wrapped round: the changes after a recent stamp, exactly, oldest first.
  ASSERT_TRUE(t.SetPostElevation(75, 75, 4.0f).ok());
  ASSERT_TRUE(t.Add(Id(2), FeatureParams::Crater(55.0, 51.0, 5.0)).ok());
  areas = t.ChangedAreasSince(seen);
  ASSERT_TRUE(areas.has_value());
  ASSERT_EQ(areas->size(), 2u);
  EXPECT_TRUE(areas->at(0).Intersects(far));
  EXPECT_FALSE(areas->at(0).Intersects(b));
  EXPECT_TRUE(areas->at(1).Intersects(b));
  EXPECT_FALSE(areas->at(1).Intersects(far));
  t.RemoveAll();
  EXPECT_FALSE(t.ChangedAreasSince(seen).has_value());
  EXPECT_TRUE(t.ChangedAreasSince(t.stamp())->empty());
}

// Each thread draws stamps from a block of its own: a terrain handed to a thread whose block is
// older than the terrain's last stamp must still draw greater stamps there, and two terrains on
// two threads never share one.
TEST(TerrainStamp, GrowsOnAThreadWithAnOlderBlockAndIsNeverShared) {
  std::promise<void> older_block_taken, terrain_made;
  std::promise<uint64_t> other_terrain_stamp;
  Terrain t(SlopedGround());
  uint64_t before = 0, after = 0;
  // The worker takes its block first and keeps it, then adds to `t` after a newer block drew.
  std::thread worker([&] {
    Terrain own(SlopedGround());
    EXPECT_TRUE(own.Add(Id(1), FeatureParams::Crater(55.0, 50.0, 5.0)).ok());
    other_terrain_stamp.set_value(own.stamp());
    older_block_taken.set_value();
    terrain_made.get_future().wait();
    before = t.stamp();
    EXPECT_TRUE(t.Add(Id(3), FeatureParams::Crater(120.0, 120.0, 5.0)).ok());
    after = t.stamp();
  });
  older_block_taken.get_future().wait();
  // A third thread takes a block newer than the worker's and stamps `t` from it.
  std::thread newer(
      [&] { EXPECT_TRUE(t.Add(Id(2), FeatureParams::Crater(80.0, 80.0, 5.0)).ok()); });
  newer.join();
  const uint64_t worker_stamp = other_terrain_stamp.get_future().get();
  EXPECT_GT(t.stamp(), worker_stamp);  // the newer block is above the worker's
  terrain_made.set_value();
  worker.join();
  EXPECT_GT(after, before);
  EXPECT_NE(after, worker_stamp);
  EXPECT_EQ(after, t.stamp());
}

}  // namespace
}  // namespace dt
