#include "runtime/vehicle_listing.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace dt {
namespace {

TEST(VehicleListingTest, ReadsLocalAndRemoteLines) {
  const auto v = ParseVehicleListing(
      "local 3 1:1:1 tank owner=1:1 x_m=100.00 y_m=12.50 z_m=100.00 heading_deg=0.00 "
      "pitch_deg=-1.20 roll_deg=0.30 speed_mps=4.00 alive=1 model_error_m=0.120 sent=3\n"
      "remote 1:2:1 jeep owner=1:2 x_m=5.00 y_m=1.00 z_m=6.00 heading_deg=90.00 pitch_deg=2.00 "
      "roll_deg=-17.50 speed_mps=0.00 alive=0 model_error_m=1.020 settled=1 age_s=0.40 "
      "updates=7\n");
  ASSERT_TRUE(v) << v.error().message;
  ASSERT_EQ(v.value().size(), 2u);
  const ListedVehicle& l = v.value()[0];
  EXPECT_TRUE(l.local);
  EXPECT_EQ(l.entity, "1:1:1");
  EXPECT_EQ(l.index, 3u);
  EXPECT_TRUE(l.alive);
  EXPECT_EQ(l.type, "tank");
  EXPECT_EQ(l.owner, "1:1");
  EXPECT_DOUBLE_EQ(l.y_m, 12.5);
  EXPECT_DOUBLE_EQ(l.speed_mps, 4.0);
  EXPECT_DOUBLE_EQ(l.model_error_m, 0.12);
  const ListedVehicle& r = v.value()[1];
  EXPECT_FALSE(r.local);
  EXPECT_EQ(r.entity, "1:2:1");
  EXPECT_EQ(r.owner, "1:2");
  EXPECT_FALSE(r.alive);
  EXPECT_DOUBLE_EQ(r.heading_deg, 90.0);
  EXPECT_DOUBLE_EQ(r.age_s, 0.4);
  EXPECT_DOUBLE_EQ(l.age_s, 0.0);
  EXPECT_DOUBLE_EQ(TiltDeg(r), 17.5);
  EXPECT_DOUBLE_EQ(TiltDeg(l), 1.2);
}

TEST(VehicleListingTest, ReadsBackTheLinesItWrites) {
  ListedVehicle local;
  local.local = true;
  local.index = 2;
  local.entity = "1:1:3";
  local.type = "bulldozer";
  local.owner = "1:1";
  local.x_m = 10.004;
  local.y_m = -2.5;
  local.z_m = 300.0;
  local.heading_deg = 359.99;
  local.pitch_deg = -4.25;
  local.roll_deg = 0.5;
  local.speed_mps = 1.75;
  local.model_error_m = 0.125;
  local.alive = false;
  local.sent = 12;
  EXPECT_EQ(VehicleLine(local),
            "local 2 1:1:3 bulldozer owner=1:1 x_m=10.00 y_m=-2.50 z_m=300.00 heading_deg=359.99 "
            "pitch_deg=-4.25 roll_deg=0.50 speed_mps=1.75 alive=0 model_error_m=0.125 sent=12");
  ListedVehicle remote = local;
  remote.local = false;
  remote.entity = "31:5:777";
  remote.owner = "1:60";
  remote.alive = true;
  remote.settled = true;
  remote.age_s = 0.25;
  remote.updates = 4;
  EXPECT_EQ(VehicleLine(remote),
            "remote 31:5:777 bulldozer owner=1:60 x_m=10.00 y_m=-2.50 z_m=300.00 "
            "heading_deg=359.99 pitch_deg=-4.25 roll_deg=0.50 speed_mps=1.75 alive=1 "
            "model_error_m=0.125 settled=1 age_s=0.25 updates=4");
  const auto back = ParseVehicleListing(VehicleLine(local) + "\n" + VehicleLine(remote));
  ASSERT_TRUE(back) << back.error().message;
  ASSERT_EQ(back.value().size(), 2u);
  EXPECT_TRUE(back.value()[0].local);
  EXPECT_EQ(back.value()[0].index, 2u);
  EXPECT_EQ(back.value()[0].entity, "1:1:3");
  EXPECT_DOUBLE_EQ(back.value()[0].x_m, 10.0);
  EXPECT_DOUBLE_EQ(back.value()[0].model_error_m, 0.125);
  EXPECT_FALSE(back.value()[1].local);
  EXPECT_EQ(back.value()[1].owner, "1:60");
  EXPECT_DOUBLE_EQ(back.value()[1].age_s, 0.25);
}

TEST(VehicleListingTest, EmptyReplyIsNoVehicles) {
  const auto v = ParseVehicleListing("");
  ASSERT_TRUE(v);
  EXPECT_TRUE(v.value().empty());
}

TEST(VehicleListingTest, RefusesWhatIsNotAVehicleLine) {
  const std::string good_keys =
      " owner=1:1 x_m=1 y_m=1 z_m=1 heading_deg=0 pitch_deg=0 roll_deg=0 speed_mps=0 "
      "model_error_m=0 alive=1";
  EXPECT_TRUE(ParseVehicleListing("local 0 1:1:1 tank" + good_keys));
  EXPECT_NE(ParseVehicleListing("local x 1:1:1 tank" + good_keys).error().message.find("index"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("local -1 1:1:1 tank" + good_keys).error().message.find("index"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("remote 1:1:1 tank owner=1:1 x_m=1 y_m=1 z_m=1 heading_deg=0 "
                                "pitch_deg=0 roll_deg=0 speed_mps=0 model_error_m=0 age_s=0")
                .error()
                .message.find("alive"),
            std::string::npos);
  EXPECT_TRUE(ParseVehicleListing("remote 1:1:1 tank" + good_keys + " age_s=0.1"));
  EXPECT_NE(ParseVehicleListing("remote 1:1:1 tank" + good_keys).error().message.find("age_s"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("local first 1:1:1 tank" + good_keys).error().message.find("first"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("ghost 1:1:1 tank" + good_keys).error().message.find("ghost"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("remote 1:1:1 tank owner=1:1 x_m=1").error().message.find("y_m"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("remote 1:1:1 tank" + good_keys + " age_s=0 pitch_deg=nan")
                .error()
                .message.find("pitch_deg"),
            std::string::npos);
  EXPECT_NE(ParseVehicleListing("remote 1:1:1 tank x_m=1").error().message.find("owner"),
            std::string::npos);
}

// A listing of `n` vehicles whose owners alternate 1:1, 1:2, as a node writes it.
std::string Listing(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) {
    ListedVehicle v;
    v.local = i % 2 == 0;
    v.index = static_cast<size_t>(i);
    v.entity = fmt::format("1:{}:{}", 1 + i % 2, i);
    v.type = "truck";
    v.owner = fmt::format("1:{}", 1 + i % 2);
    v.x_m = i;
    text += (text.empty() ? "" : "\n") + VehicleLine(v);
  }
  return text;
}

TEST(VehiclePageTest, TheDefaultPageIsTheWholeListing) {
  const std::string all = Listing(7);
  EXPECT_EQ(PageVehicleListing(all, VehiclePage{}), all);
}

TEST(VehiclePageTest, APageHoldsItsLinesThenHowManyMore) {
  const std::string all = Listing(10);
  const std::string page = PageVehicleListing(all, VehiclePage{"", 3, 4});
  const auto v = ParseVehicleListing(page);
  ASSERT_TRUE(v) << v.error().message;
  ASSERT_EQ(v.value().size(), 4u);
  EXPECT_EQ(v.value()[0].entity, "1:2:3");
  EXPECT_EQ(v.value()[3].entity, "1:1:6");
  EXPECT_TRUE(page.ends_with("\n3 more (--offset 7)")) << page;
  // The last page says nothing more; a page past the end is empty.
  const std::string last = PageVehicleListing(all, VehiclePage{"", 7, 4});
  EXPECT_EQ(ParseVehicleListing(last).value().size(), 3u);
  EXPECT_EQ(last.find("more"), std::string::npos) << last;
  EXPECT_EQ(PageVehicleListing(all, VehiclePage{"", 12, 4}), "");
}

TEST(VehiclePageTest, AnOwnerSelectsItsLinesBeforeThePage) {
  const std::string all = Listing(10);
  const std::string page = PageVehicleListing(all, VehiclePage{"1:2", 1, 2});
  const auto v = ParseVehicleListing(page);
  ASSERT_TRUE(v) << v.error().message;
  ASSERT_EQ(v.value().size(), 2u);
  EXPECT_EQ(v.value()[0].entity, "1:2:3");
  EXPECT_EQ(v.value()[1].entity, "1:2:5");
  EXPECT_TRUE(page.ends_with("\n2 more (--offset 3)")) << page;
  EXPECT_EQ(PageVehicleListing(all, VehiclePage{"9:9", 0, std::nullopt}), "");
}

TEST(VehiclePageTest, ThirtyThousandVehiclesAnswerOnePage) {
  const std::string all = Listing(30000);
  const std::string page = PageVehicleListing(all, VehiclePage{"", 0, kDefaultVehicleLimit});
  EXPECT_EQ(ParseVehicleListing(page).value().size(), kDefaultVehicleLimit);
  EXPECT_TRUE(page.ends_with(
      fmt::format("\n{} more (--offset {})", 30000 - kDefaultVehicleLimit, kDefaultVehicleLimit)));
  EXPECT_LT(page.size() * 20, all.size());
}

}  // namespace
}  // namespace dt
