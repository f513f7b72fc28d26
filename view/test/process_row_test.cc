// Tests reading a process's `status` reply into the panel's row and its vehicles.
#include <gtest/gtest.h>

#include "view/process_poller.h"
#include "view/process_row.h"

namespace dt {
namespace {

TEST(ProcessRow, StatusLinesFillTheRow) {
  ProcessRow r;
  ParseStatusInto(
      "name node-1\nsigned_on 1\ncaught_up 0\ndiverged 1\nfeatures 12\ndigest abc123\nsent 40\n"
      "received 99\nvoided 3\n",
      r);
  EXPECT_TRUE(r.signed_on);
  EXPECT_FALSE(r.caught_up);
  EXPECT_TRUE(r.diverged);
  EXPECT_EQ(r.features, 12);
  EXPECT_EQ(r.digest, "abc123");
  EXPECT_EQ(r.counters.at("sent"), 40);
  EXPECT_EQ(r.counters.at("received"), 99);
  EXPECT_EQ(r.counters.count("voided"), 0u);
}

}  // namespace
}  // namespace dt
