// Tests reading a process's `status` reply into the panel's row and its vehicles.
#include <gtest/gtest.h>

#include "runtime/status_report.h"
#include "view/process_poller.h"
#include "view/process_row.h"

namespace dt {
namespace {

TEST(ProcessRow, StatusLinesFillTheRow) {
  StatusReport status;
  status.name = "node-1";
  status.signed_on = true;
  status.caught_up = false;
  status.diverged = true;
  status.features = 12;
  status.digest = "abc123";
  status.sent = 40;
  status.received = 99;
  status.voided = 3;
  ProcessRow r;
  ASSERT_TRUE(ParseStatusInto(status.ToText(), r));
  EXPECT_TRUE(r.signed_on);
  EXPECT_FALSE(r.caught_up);
  EXPECT_TRUE(r.diverged);
  EXPECT_EQ(r.features, 12);
  EXPECT_EQ(r.digest, "abc123");
  EXPECT_EQ(r.counters.at("sent"), 40);
  EXPECT_EQ(r.counters.at("received"), 99);
  EXPECT_EQ(r.counters.count("voided"), 0u);
}

TEST(ProcessRow, AStatusThatDoesNotReadLeavesTheRowAndSaysWhy) {
  ProcessRow r;
  r.digest = "before";
  const Status read = ParseStatusInto("name node-1\nsigned_on 1\n", r);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error().message, "status has no \"address\" line");
  EXPECT_EQ(r.digest, "before");
  EXPECT_FALSE(r.signed_on);
}

}  // namespace
}  // namespace dt
