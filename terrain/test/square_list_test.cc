#include "terrain/square_list.h"

#include <algorithm>
#include <memory>
#include <span>
#include <vector>

#include <gtest/gtest.h>

namespace dt {
namespace {

std::vector<const Feature*> Sorted(std::span<const Feature* const> s) {
  std::vector<const Feature*> v(s.begin(), s.end());
  std::sort(v.begin(), v.end());
  return v;
}

// Grows past the inline slots and shrinks back, against a plain vector doing the same.
TEST(SquareList, MatchesAVectorAcrossTheInlineLimit) {
  // Distinct addresses stand for features: the list never dereferences them.
  std::vector<char> storage(16);
  auto at = [&](int k) { return reinterpret_cast<const Feature*>(&storage[k]); };
  SquareList list;
  std::vector<const Feature*> expected;
  EXPECT_TRUE(list.empty());
  for (int k = 0; k < 8; ++k) {
    list.push_back(at(k));
    expected.push_back(at(k));
    EXPECT_EQ(Sorted(list.features()), Sorted(expected)) << k;
  }
  for (int k : {3, 0, 7, 5, 1}) {
    list.erase(at(k));
    expected.erase(std::remove(expected.begin(), expected.end(), at(k)), expected.end());
    EXPECT_EQ(Sorted(list.features()), Sorted(expected)) << k;
  }
  EXPECT_EQ(list.features().size(), 3u);
  list.push_back(at(9));
  list.push_back(at(9));
  list.erase(at(9));  // every occurrence
  EXPECT_EQ(list.features().size(), 3u);
  list.erase(at(12));  // absent: nothing changes
  EXPECT_EQ(list.features().size(), 3u);
  SquareList moved = std::move(list);
  EXPECT_EQ(Sorted(moved.features()), Sorted(expected));
  moved.clear();
  EXPECT_TRUE(moved.empty());
  EXPECT_TRUE(moved.features().empty());
}

// Past the inline slots the list grows its own array by doubling: the features stay whole across
// each growth and across moves, inline or not.
TEST(SquareList, GrowsPastItsArrayAndMovesEitherWay) {
  static_assert(sizeof(SquareList) == 40);  // the per-square cost docs/real-ground.md states
  std::vector<char> storage(64);
  auto at = [&](int k) { return reinterpret_cast<const Feature*>(&storage[k]); };
  SquareList list;
  std::vector<const Feature*> expected;
  for (int k = 0; k < 40; ++k) {
    list.push_back(at(k));
    expected.push_back(at(k));
  }
  EXPECT_EQ(Sorted(list.features()), Sorted(expected));
  SquareList moved;
  moved.push_back(at(50));  // an inline list, overwritten by the heap one
  moved = std::move(list);
  EXPECT_TRUE(list.empty());
  EXPECT_EQ(Sorted(moved.features()), Sorted(expected));
  for (int k = 0; k < 37; ++k) moved.erase(at(k));  // back to three: inline again
  EXPECT_EQ(Sorted(moved.features()), Sorted(std::vector<const Feature*>{at(37), at(38), at(39)}));
  moved.push_back(at(41));
  SquareList inline_moved(std::move(moved));
  EXPECT_TRUE(moved.empty());
  EXPECT_EQ(Sorted(inline_moved.features()),
            Sorted(std::vector<const Feature*>{at(37), at(38), at(39), at(41)}));
}

}  // namespace
}  // namespace dt
