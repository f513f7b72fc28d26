// Tests the DIS time stamp: units of 3600 s / 2^31 past the hour, low bit absolute/relative.
#include "pdu/dis_time.h"

#include <gtest/gtest.h>

namespace dt {
namespace {

TEST(DisTime, EncodesUnitsPastTheHourAboveTheAbsoluteBit) {
  EXPECT_EQ(EncodeDisTimestamp(0.0, true), 1u);
  EXPECT_EQ(EncodeDisTimestamp(0.0, false), 0u);
  // Half an hour is 2^30 units, shifted left past the absolute bit.
  EXPECT_EQ(EncodeDisTimestamp(1800.0, true), (1u << 31) | 1u);
  EXPECT_EQ(EncodeDisTimestamp(1800.0, false), 1u << 31);
  // One unit.
  EXPECT_EQ(EncodeDisTimestamp(kDisTimeUnitS * 1.5, false), 2u);
  // The last unit of the hour.
  EXPECT_EQ(EncodeDisTimestamp(3599.9999999, true), 0xFFFFFFFFu);
}

TEST(DisTime, WrapsIntoTheHourAndDecodes) {
  const uint32_t t = EncodeDisTimestamp(3600.0 * 5 + 123.456, true);
  EXPECT_TRUE(DisTimestampIsAbsolute(t));
  EXPECT_NEAR(DisTimestampSeconds(t), 123.456, kDisTimeUnitS);
  EXPECT_FALSE(DisTimestampIsAbsolute(EncodeDisTimestamp(10, false)));
}

TEST(DisTime, SystemClockTimeIsAbsoluteAndPastTheHour) {
  using namespace std::chrono;
  const system_clock::time_point tp{seconds(3600 * 400000 + 61)};
  const uint32_t t = DisTimestampAt(tp);
  EXPECT_TRUE(DisTimestampIsAbsolute(t));
  EXPECT_NEAR(DisTimestampSeconds(t), 61.0, kDisTimeUnitS);
}

}  // namespace
}  // namespace dt
