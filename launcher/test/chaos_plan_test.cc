#include "launcher/chaos_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace dt {
namespace {

const std::vector<std::string> kTargets = {"server", "node-1", "node-2", "node-3"};

ChaosSettings Settings(uint64_t seed) {
  ChaosSettings s;
  s.duration_s = 1000.0;
  s.period_s = 10.0;
  s.max_down = 2;
  s.down_min_s = 1.0;
  s.down_max_s = 4.0;
  s.seed = seed;
  return s;
}

bool SamePlan(const std::vector<ChaosRound>& a, const std::vector<ChaosRound>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].at_s != b[i].at_s || a[i].count != b[i].count || a[i].order != b[i].order ||
        a[i].down_s != b[i].down_s) {
      return false;
    }
  }
  return true;
}

TEST(ChaosPlanTest, OneSeedOnePlanAnotherSeedAnother) {
  const auto a = PlanChaos(Settings(7), kTargets);
  EXPECT_TRUE(SamePlan(a, PlanChaos(Settings(7), kTargets)));
  EXPECT_FALSE(SamePlan(a, PlanChaos(Settings(8), kTargets)));
}

TEST(ChaosPlanTest, RoundsKeepToTheSettings) {
  const ChaosSettings s = Settings(3);
  const auto plan = PlanChaos(s, kTargets);
  // 1000 s at a mean of 10 s: about 100 rounds; far fewer or more means the gaps are wrong.
  EXPECT_GT(plan.size(), 80u);
  EXPECT_LT(plan.size(), 120u);
  double previous_s = 0.0;
  std::set<int> counts;
  std::set<std::string> first;
  const std::vector<std::string> sorted_targets = [] {
    auto t = kTargets;
    std::sort(t.begin(), t.end());
    return t;
  }();
  for (const ChaosRound& r : plan) {
    const double gap_s = r.at_s - previous_s;
    EXPECT_GE(gap_s, 0.5 * s.period_s);
    EXPECT_LE(gap_s, 1.5 * s.period_s);
    EXPECT_LT(r.at_s, s.duration_s);
    previous_s = r.at_s;
    EXPECT_GE(r.count, 1);
    EXPECT_LE(r.count, s.max_down);
    counts.insert(r.count);
    auto order = r.order;
    std::sort(order.begin(), order.end());
    EXPECT_EQ(order, sorted_targets);  // a permutation of the targets
    first.insert(r.order.front());
    ASSERT_EQ(r.down_s.size(), static_cast<size_t>(s.max_down));
    for (double d : r.down_s) {
      EXPECT_GE(d, s.down_min_s);
      EXPECT_LE(d, s.down_max_s);
    }
  }
  EXPECT_EQ(counts, (std::set<int>{1, 2}));
  EXPECT_EQ(first.size(), kTargets.size());  // every target is some round's first victim
}

TEST(ChaosPlanTest, ShortChaosHasNoRoundPastItsDuration) {
  ChaosSettings s = Settings(1);
  s.duration_s = 4.0;  // below the shortest first gap (5 s)
  EXPECT_TRUE(PlanChaos(s, kTargets).empty());
}

TEST(ChaosPlanTest, RefusesImpossibleSettings) {
  EXPECT_THROW(PlanChaos(Settings(1), {}), std::invalid_argument);
  ChaosSettings s = Settings(1);
  s.max_down = 5;
  EXPECT_THROW(PlanChaos(s, kTargets), std::invalid_argument);
  s.max_down = 0;
  EXPECT_THROW(PlanChaos(s, kTargets), std::invalid_argument);
  s = Settings(1);
  s.period_s = 0.0;
  EXPECT_THROW(PlanChaos(s, kTargets), std::invalid_argument);
  s = Settings(1);
  s.down_min_s = 5.0;
  EXPECT_THROW(PlanChaos(s, kTargets), std::invalid_argument);
}

}  // namespace
}  // namespace dt
