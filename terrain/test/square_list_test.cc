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

}  // namespace
}  // namespace dt
