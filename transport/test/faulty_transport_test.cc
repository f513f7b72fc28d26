// Tests FaultyTransport over memq: partitions by the sender in the bytes, delays in calls and in
// milliseconds with jitter, the extra delay between sites, drops, and determinism.
#include "transport/faulty_transport.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>
#include <tuple>

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

TEST(FaultModel, DelayRangeIsDelayPlusOrMinusJitter) {
  EXPECT_EQ(DelayRange(100, 20), (std::pair<int64_t, int64_t>{80, 120}));
  EXPECT_EQ(DelayRange(50, 0), (std::pair<int64_t, int64_t>{50, 50}));
  EXPECT_THROW(DelayRange(10, 11), std::invalid_argument);
  EXPECT_THROW(DelayRange(-1, 0), std::invalid_argument);
}

TEST(FaultModel, JitterSpreadsDelaysOverTheWholeRange) {
  FaultConfig f;
  std::tie(f.min_delay, f.max_delay) = DelayRange(40, 10);
  FaultModel m(f, 5);
  std::set<int64_t> seen;
  for (int i = 0; i < 2000; ++i) {
    const std::vector<int64_t> d = m.Fate({2, 2}, {1, 1});
    ASSERT_EQ(d.size(), 1u);
    ASSERT_GE(d[0], 30);
    ASSERT_LE(d[0], 50);
    seen.insert(d[0]);
  }
  EXPECT_EQ(seen.size(), 21u);  // every value of [30, 50]
}

TEST(FaultModel, OtherSiteDelayAppliesBetweenSitesOnly) {
  FaultConfig f;
  f.min_delay = f.max_delay = 2;
  f.other_site_min_delay = 40;
  f.other_site_max_delay = 60;
  FaultModel m(f, 3);
  for (int i = 0; i < 200; ++i) {
    EXPECT_EQ(m.Fate({1, 2}, {1, 1}), (std::vector<int64_t>{2}));  // same site
    const std::vector<int64_t> d = m.Fate({2, 1}, {1, 1});
    ASSERT_EQ(d.size(), 1u);
    EXPECT_GE(d[0], 42);
    EXPECT_LE(d[0], 62);
  }
  f.other_site_min_delay = 61;  // min above max
  EXPECT_THROW(m.set_config(f), std::invalid_argument);
}

TEST(FaultModel, UnusedOtherSiteDelayDrawsNothing) {
  // Seeds give the decisions they gave before the other-site delay existed.
  FaultConfig f;
  f.drop_probability = 0.3;
  f.max_delay = 5;
  FaultModel a(f, 11);
  FaultModel b(f, 11);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(a.Fate({2, 1}, {1, 1}), b.Fate({1, 2}, {1, 1}));
  }
}

TEST(FaultyTransport, JitteredMillisecondDelaysHoldEveryMessageAtLeastTheMinimum) {
  FaultConfig f;
  std::tie(f.min_delay, f.max_delay) = DelayRange(30, 10);
  FaultyTransport t(std::make_unique<LcmTransport>("memq://", 1), {1, 1}, f, 1,
                    DelayUnit::kMilliseconds);
  std::vector<std::chrono::steady_clock::time_point> arrived;
  t.Subscribe(PduType::kDestruct, [&](std::span<const uint8_t>) {
    arrived.push_back(std::chrono::steady_clock::now());
  });
  const auto start = std::chrono::steady_clock::now();
  for (int i = 1; i <= 20; ++i) ASSERT_TRUE(t.Publish(PduType::kDestruct, From({2, 2}, i)).ok());
  EXPECT_EQ(t.HandleTimeout(0).value(), 0);
  EXPECT_EQ(t.held(), 20u);
  // HandleTimeout sleeps until the next release, so the loop ends once the last is due.
  for (int i = 0; i < 100 && arrived.size() < 20; ++i) ASSERT_TRUE(t.HandleTimeout(1000).ok());
  ASSERT_EQ(arrived.size(), 20u);
  for (const auto& at : arrived) EXPECT_GE(at - start, std::chrono::milliseconds(20));
}

}  // namespace
}  // namespace dt
