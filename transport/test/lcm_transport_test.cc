// Tests LcmTransport over memq: per-type channels, bursts, size limit, fd, URL handling.
#include "transport/lcm_transport.h"

#include <poll.h>

#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

namespace dt {
namespace {

std::vector<uint8_t> Payload(size_t n, uint8_t seed) {
  std::vector<uint8_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(seed + i * 7);
  return v;
}

TEST(LcmTransport, MemqDeliversEachTypeOnlyToItsSubscribers) {
  LcmTransport t("memq://", 3);
  std::map<PduType, std::vector<std::vector<uint8_t>>> got;
  for (PduType type : kAllPduTypes) {
    t.Subscribe(type, [&got, type](std::span<const uint8_t> b) {
      got[type].emplace_back(b.begin(), b.end());
    });
  }
  uint8_t seed = 1;
  for (PduType type : kAllPduTypes) ASSERT_TRUE(t.Publish(type, Payload(20, seed++)).ok());
  auto n = t.HandleTimeout(0);
  ASSERT_TRUE(n.ok());
  EXPECT_EQ(n.value(), static_cast<int>(kAllPduTypes.size()));
  seed = 1;
  for (PduType type : kAllPduTypes) {
    ASSERT_EQ(got[type].size(), 1u) << PduTypeName(type);
    EXPECT_EQ(got[type][0], Payload(20, seed++));
  }
}

TEST(LcmTransport, ABurstIsNotCutByTheDefaultQueueOfThirty) {
  LcmTransport t("memq://", 1);
  int received = 0;
  t.Subscribe(PduType::kUpdate, [&](std::span<const uint8_t>) { ++received; });
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(t.Publish(PduType::kUpdate, Payload(100, 3)).ok());
  int handled = 0;
  for (int round = 0; round < 10 && handled < 1000; ++round) {
    auto n = t.HandleTimeout(0);
    ASSERT_TRUE(n.ok());
    handled += n.value();
  }
  EXPECT_EQ(received, 1000);
}

TEST(LcmTransport, RefusesPdusBiggerThanOneDatagram) {
  LcmTransport t("memq://", 1);
  EXPECT_TRUE(t.Publish(PduType::kConstruct, Payload(kMaxPduBytes, 0)).ok());
  Status s = t.Publish(PduType::kConstruct, Payload(kMaxPduBytes + 1, 0));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("1401"), std::string::npos) << s.error().message;
}

TEST(LcmTransport, FdBecomesReadableWhenThereIsWork) {
  LcmTransport t("memq://", 1);
  t.Subscribe(PduType::kDestruct, [](std::span<const uint8_t>) {});
  pollfd p{t.Fd(), POLLIN, 0};
  ASSERT_GE(p.fd, 0);
  EXPECT_EQ(poll(&p, 1, 0), 0);
  ASSERT_TRUE(t.Publish(PduType::kDestruct, Payload(4, 0)).ok());
  EXPECT_EQ(poll(&p, 1, 1000), 1);
  ASSERT_TRUE(t.HandleTimeout(0).ok());
}

TEST(LcmTransport, AddsTheReceiveBufferToUdpmUrls) {
  EXPECT_THROW(MakeTransport("tcp://x", 1), std::invalid_argument);
  LcmTransport t("memq://", 1);
  EXPECT_EQ(t.lcm_url(), "memq://");
}

TEST(LcmTransport, ChannelNamesCarryTheExercise) {
  EXPECT_EQ(ChannelName(7, PduType::kConstruct), "DT7_CONSTRUCT");
  EXPECT_EQ(ChannelName(255, PduType::kPlayback), "DT255_PLAYBACK");
}

}  // namespace
}  // namespace dt
