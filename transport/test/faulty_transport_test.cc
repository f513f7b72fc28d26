// Tests FaultyTransport over memq: partitions by the sender in the bytes, delays in calls,
// drops, and determinism.
#include "transport/faulty_transport.h"

#include <algorithm>
#include <chrono>
#include <set>

#include <gtest/gtest.h>

#include "pdu/pdu_traits.h"
#include "pdu/test/sample_pdus.h"
#include "transport/lcm_transport.h"

namespace dt {
namespace {

std::vector<uint8_t> From(NodeAddress sender, int64_t number) {
  auto pdu = sample::Destruct();
  pdu.sender = ToPdu(sender);
  pdu.sender_seq = number;
  return EncodePdu(pdu);
}

struct Rig {
  explicit Rig(FaultConfig f, uint64_t seed = 1)
      : t(std::make_unique<LcmTransport>("memq://", 1), kLocal, f, seed) {
    t.Subscribe(PduType::kDestruct, [this](std::span<const uint8_t> b) {
      dtpdu::destruct_t pdu;
      if (!DecodePdu(b, pdu)) got.push_back(pdu.sender_seq);
    });
  }
  static constexpr NodeAddress kLocal{1, 1};
  FaultyTransport t;
  std::vector<int64_t> got;
};

TEST(FaultyTransport, PartitionsUseTheSenderInTheBytes) {
  Rig rig({});
  rig.t.faults().Partition({Rig::kLocal}, {{2, 2}});
  ASSERT_TRUE(rig.t.Publish(PduType::kDestruct, From({2, 2}, 1)).ok());
  ASSERT_TRUE(rig.t.Publish(PduType::kDestruct, From({3, 3}, 2)).ok());
  ASSERT_TRUE(rig.t.Publish(PduType::kDestruct, From(Rig::kLocal, 3)).ok());
  ASSERT_TRUE(rig.t.HandleTimeout(0).ok());
  EXPECT_EQ(rig.got, (std::vector<int64_t>{2, 3}));
  EXPECT_EQ(rig.t.dropped(), 1u);
}

TEST(FaultyTransport, DelaysCountHandleCalls) {
  FaultConfig f;
  f.min_delay = 2;
  f.max_delay = 2;
  Rig rig(f);
  ASSERT_TRUE(rig.t.Publish(PduType::kDestruct, From({2, 2}, 1)).ok());
  EXPECT_EQ(rig.t.HandleTimeout(0).value(), 0);
  EXPECT_EQ(rig.t.held(), 1u);
  EXPECT_EQ(rig.t.HandleTimeout(0).value(), 0);
  EXPECT_EQ(rig.t.HandleTimeout(0).value(), 1);
  EXPECT_EQ(rig.got, (std::vector<int64_t>{1}));
}

TEST(FaultyTransport, DelaysCanCountMilliseconds) {
  FaultConfig f;
  f.min_delay = 30;
  f.max_delay = 30;
  FaultyTransport t(std::make_unique<LcmTransport>("memq://", 1), {1, 1}, f, 1,
                    DelayUnit::kMilliseconds);
  int got = 0;
  t.Subscribe(PduType::kDestruct, [&](std::span<const uint8_t>) { ++got; });
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(t.Publish(PduType::kDestruct, From({2, 2}, 1)).ok());
  EXPECT_EQ(t.HandleTimeout(0).value(), 0);
  EXPECT_EQ(t.held(), 1u);
  // HandleTimeout waits until the release time, so a few calls with a long timeout suffice.
  for (int i = 0; i < 5 && got == 0; ++i) ASSERT_TRUE(t.HandleTimeout(1000).ok());
  EXPECT_EQ(got, 1);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(30));
}

std::vector<int64_t> RunLossy(uint64_t seed) {
  FaultConfig f;
  f.drop_probability = 0.25;
  f.duplicate_probability = 0.25;
  f.max_delay = 3;
  f.reorder_probability = 0.3;
  f.reorder_window = 4;
  Rig rig(f, seed);
  for (int i = 1; i <= 300; ++i) {
    EXPECT_TRUE(rig.t.Publish(PduType::kDestruct, From({2, 2}, i)).ok());
    EXPECT_TRUE(rig.t.HandleTimeout(0).ok());
  }
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(rig.t.HandleTimeout(0).ok());
  EXPECT_EQ(rig.t.held(), 0u);
  return rig.got;
}

TEST(FaultyTransport, SeededFaultsAreDeterministic) {
  const auto a = RunLossy(9);
  EXPECT_EQ(a, RunLossy(9));
  EXPECT_NE(a, RunLossy(10));
  std::set<int64_t> distinct(a.begin(), a.end());
  EXPECT_LT(distinct.size(), 300u);                  // some dropped
  EXPECT_GT(a.size(), distinct.size());              // some duplicated
  EXPECT_FALSE(std::is_sorted(a.begin(), a.end()));  // some reordered
}

}  // namespace
}  // namespace dt
