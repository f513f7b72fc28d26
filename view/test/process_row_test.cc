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

TEST(ProcessRow, VehicleLinesBecomeVehicles) {
  const auto v = ParseStatusVehicles(
      "features 1\nvehicle 0 tank x_m=300.5 z_m=310 y_m=2 heading_rad=1.5 speed_mps=4 "
      "on_bridge=- alive=1 model=physical damage=none\n"
      "vehicle 1 jeep x_m=10 z_m=20 y_m=2 heading_rad=0 speed_mps=0 on_bridge=- alive=0\n",
      "node-1");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].id, "node-1/0");
  EXPECT_EQ(v[0].type, "tank");
  EXPECT_DOUBLE_EQ(v[0].x_m, 300.5);
  EXPECT_DOUBLE_EQ(v[0].heading_rad, 1.5);
  EXPECT_TRUE(v[0].alive);
  EXPECT_FALSE(v[1].alive);
  EXPECT_EQ(v[1].owner, "node-1");
}

}  // namespace
}  // namespace dt
