// FeatureTable: dense per-origin arrays, the hash map for numbers they do not reach, and the move
// of such features into an array that grows to reach them.
#include "terrain/feature_table.h"

#include <map>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/test/sample_terrain.h"

namespace dt {
namespace {

std::unique_ptr<Feature> Crater(FeatureId id) {
  static const HeightGrid ground = test::SampleGround();
  auto made = MakeFeature(id, FeatureParams::Crater(40.0, 40.0, 2.0), ground);
  EXPECT_TRUE(made.ok());
  return std::move(made).value();
}

// The table's answers against a std::map holding the same IDs.
void ExpectSame(const FeatureTable& table, const std::map<FeatureId, const Feature*>& expected) {
  ASSERT_EQ(table.size(), expected.size());
  std::map<FeatureId, const Feature*> seen;
  table.ForEach([&](const Feature& f) { EXPECT_TRUE(seen.emplace(f.id(), &f).second); });
  EXPECT_EQ(seen, expected);
  for (const auto& [id, f] : expected) EXPECT_EQ(table.Find(id), f) << id.ToString();
}

TEST(FeatureTable, KeepsPointersAndAnswersLikeAMapUnderMixedOperations) {
  // Consecutive numbers of a few origins, far numbers (kept aside, then reached by a growing
  // array), repeats after erasure, and replacements, in one random order.
  std::mt19937 rng(7);
  FeatureTable table;
  std::map<FeatureId, const Feature*> expected;
  std::map<uint32_t, uint32_t> next;  // per host, the next consecutive number
  for (int step = 0; step < 6000; ++step) {
    const uint16_t host = static_cast<uint16_t>(1 + rng() % 3);
    const int op = static_cast<int>(rng() % 10);
    FeatureId id{1, host, 0};
    if (op < 6) {
      id.number = ++next[host];
    } else if (op == 6) {
      id.number = next[host] + 1 + static_cast<uint32_t>(rng() % 2000);  // ahead of the run
    } else {
      id.number = 1 + static_cast<uint32_t>(rng() % (next[host] + 1));
    }
    const bool held = expected.count(id) != 0;
    if (op == 9 && held) {
      EXPECT_TRUE(table.Erase(id));
      expected.erase(id);
      EXPECT_EQ(table.Find(id), nullptr);
    } else if (op == 8 && held) {
      expected[id] = table.Replace(id, Crater(id));
    } else if (!held) {
      expected[id] = table.Insert(id, Crater(id));
    } else {
      EXPECT_NE(table.Find(id), nullptr);
    }
  }
  ExpectSame(table, expected);
  EXPECT_FALSE(table.Erase({1, 9, 1}));  // an origin never seen
  EXPECT_EQ(table.Find({1, 9, 1}), nullptr);

  FeatureTable moved = std::move(table);
  ExpectSame(moved, expected);
  EXPECT_EQ(table.size(), 0u);  // left empty on purpose: read after the move
  EXPECT_EQ(table.Find(expected.begin()->first), nullptr);
}

TEST(FeatureTable, FarAndHostileNumbersCostNoArraySlots) {
  FeatureTable table;
  // One feature at each of 1000 numbers spread over the 32-bit range: the arrays stay small.
  for (uint32_t k = 1; k <= 1000; ++k) {
    const FeatureId id{1, 1, k * 4'000'000u};
    table.Insert(id, Crater(id));
  }
  EXPECT_EQ(table.size(), 1000u);
  EXPECT_LE(table.dense_slots(), 16u);  // one array of the latest, the others aside
  // A run from 1 grows the origin's array; its slots stay within twice the features plus the
  // slack, and the far ones are still found.
  for (uint32_t n = 1; n <= 5000; ++n) table.Insert({1, 1, n}, Crater({1, 1, n}));
  EXPECT_LE(table.dense_slots(), 2 * 5000 + FeatureTable::kDenseSlack + 2);
  EXPECT_GE(table.dense_slots(), 5001u);
  EXPECT_NE(table.Find({1, 1, 4'000'000u}), nullptr);
  EXPECT_NE(table.Find({1, 1, 4000}), nullptr);
  EXPECT_EQ(table.size(), 6000u);
}

TEST(FeatureTable, AFeatureKeptAsideMovesIntoTheArrayThatReachesIt) {
  FeatureTable table;
  const FeatureId far{2, 3, 1000};
  const Feature* f = table.Insert(far, Crater(far));
  EXPECT_EQ(table.dense_slots(), 16u);  // an array from 1000
  // 1 is too far below for that array: it starts again from 1, and 1000 waits aside.
  for (uint32_t n = 1; n < 1000; ++n) table.Insert({2, 3, n}, Crater({2, 3, n}));
  EXPECT_GE(table.dense_slots(), 1001u);  // the array reaches 1000 now
  EXPECT_EQ(table.Find(far), f);          // the same object, moved by pointer
  EXPECT_TRUE(table.Erase(far));
  EXPECT_EQ(table.Find(far), nullptr);
  EXPECT_EQ(table.size(), 999u);
}

TEST(FeatureTable, ARunPastAReservedBlockAndOlderNumbersBelowItAreKeptInOneArray) {
  // A node's numbers start past the block it reserved (4097 here); a late joiner hears its live
  // features first and the older ones played back afterwards, from 1 up.
  FeatureTable table;
  for (uint32_t n = 4097; n <= 6000; ++n) table.Insert({1, 1, n}, Crater({1, 1, n}));
  EXPECT_LE(table.dense_slots(), 2 * 1904 + FeatureTable::kDenseSlack + 2);
  for (uint32_t n = 4096; n >= 1; --n) table.Insert({1, 1, n}, Crater({1, 1, n}));
  EXPECT_EQ(table.size(), 6000u);
  EXPECT_GE(table.dense_slots(), 6000u);  // one array from 1 to 6000: nothing left aside
  EXPECT_LE(table.dense_slots(), 2 * 6000 + FeatureTable::kDenseSlack + 2);
  for (uint32_t n = 1; n <= 6000; ++n) ASSERT_NE(table.Find({1, 1, n}), nullptr) << n;
}

}  // namespace
}  // namespace dt
