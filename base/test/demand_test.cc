#include "base/demand.h"

#include <string>

#include <gtest/gtest.h>

namespace dt {
namespace {

// Demands sum == 4; *line is set to the check's line.
void DemandFour(int sum, int* line) {
  *line = __LINE__ + 1;
  DT_DEMAND(sum == 4);
}

// Reaches DT_UNREACHABLE() if told to; *line is set to its line.
void MaybeReachUnreachable(bool reach, int* line) {
  *line = __LINE__ + 1;
  if (reach) DT_UNREACHABLE();
}

// The message names the check, its file, line and function: nothing else tells which of the
// program's checks failed.
TEST(DemandDeathTest, FalsePrintsTheConditionFileAndLineThenAborts) {
  int line = 0;
  DemandFour(4, &line);
  int ignored = 0;
  EXPECT_DEATH(DemandFour(5, &ignored),
               "dynterrain: DT_DEMAND\\(sum == 4\\) failed at "
               "[^ ]*base/test/demand_test\\.cc:" +
                   std::to_string(line) + " in DemandFour\n");
}

TEST(DemandDeathTest, UnreachablePrintsFileAndLineThenAborts) {
  int line = 0;
  MaybeReachUnreachable(false, &line);
  int ignored = 0;
  EXPECT_DEATH(MaybeReachUnreachable(true, &ignored),
               "dynterrain: DT_UNREACHABLE\\(\\) reached at [^ ]*base/test/demand_test\\.cc:" +
                   std::to_string(line) + " in MaybeReachUnreachable\n");
}

// A check that holds does nothing but evaluate its condition, once.
TEST(DemandTest, TrueEvaluatesTheConditionOnceAndGoesOn) {
  int evaluated = 0;
  DT_DEMAND(++evaluated == 1);
  EXPECT_EQ(evaluated, 1);
  int line = 0;
  DemandFour(4, &line);
  EXPECT_GT(line, 0);
}

// One statement: it takes an if's place without braces and leaves the else to its own if.
TEST(DemandTest, IsOneStatement) {
  bool checked = false;
  bool other = false;
  if (checked)
    DT_DEMAND(checked);
  else
    other = true;
  EXPECT_TRUE(other);
}

}  // namespace
}  // namespace dt
