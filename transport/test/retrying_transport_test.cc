// Tests RetryingTransport: failed publishes queued and retried in order, per channel, within a
// bound that refuses (and counts) rather than drops, over a fake carrier and over SimNetwork.
#include "transport/retrying_transport.h"

#include <map>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "pdu/pdu_traits.h"
#include "pdu/test/sample_pdus.h"
#include "simulation/sim_network.h"

namespace dt {
namespace {

// A carrier whose writes fail on demand; it records what it took and how long it was asked to
// wait.
class FakeCarrier final : public Transport {
 public:
  struct Sent {
    PduType type;
    uint8_t marker;
    bool operator==(const Sent&) const = default;
  };
  Status Publish(PduType type, std::span<const uint8_t> bytes) override {
    ++publish_calls;
    if (fail_all || failing.count(type) != 0 || fail_next > 0) {
      if (fail_next > 0) --fail_next;
      return Error{"Timeout"};
    }
    sent.push_back({type, bytes.empty() ? uint8_t{0} : bytes[0]});
    return Status::Ok();
  }
  void Subscribe(PduType type, Handler handler) override { handlers[type].push_back(handler); }
  Result<int> HandleTimeout(int timeout_ms) override {
    waits_ms.push_back(timeout_ms);
    return 0;
  }
  int Fd() const override { return 42; }
  std::string Url() const override { return "fake://"; }

  bool fail_all = false;
  int fail_next = 0;
  std::set<PduType> failing;
  int publish_calls = 0;
  std::vector<Sent> sent;
  std::vector<int> waits_ms;
  std::map<PduType, std::vector<Handler>> handlers;
};

// One byte, the marker, stands for a PDU: RetryingTransport never looks inside.
std::vector<uint8_t> Bytes(uint8_t marker) { return {marker}; }

struct Rig {
  Rig(size_t max_queued = RetryingTransport::kDefaultMaxQueued) {
    auto c = std::make_unique<FakeCarrier>();
    carrier = c.get();
    retrying = std::make_unique<RetryingTransport>(std::move(c), max_queued);
  }
  FakeCarrier* carrier;
  std::unique_ptr<RetryingTransport> retrying;
};

TEST(RetryingTransport, SendsAtOnceWhileTheCarrierTakesWrites) {
  Rig rig;
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(1)).ok());
  EXPECT_EQ(rig.carrier->sent, (std::vector<FakeCarrier::Sent>{{PduType::kUpdate, 1}}));
  const auto c = rig.retrying->counters();
  EXPECT_EQ(c.queued, 0u);
  EXPECT_EQ(c.retried, 0u);
  EXPECT_EQ(c.failed_writes, 0u);
  EXPECT_EQ(c.given_up, 0u);
}

TEST(RetryingTransport, QueuesAFailedPublishAndSendsItInOrderOnTheNextPublish) {
  Rig rig;
  rig.carrier->fail_all = true;
  for (uint8_t m = 1; m <= 3; ++m) {
    EXPECT_TRUE(rig.retrying->Publish(PduType::kConstruct, Bytes(m)).ok()) << int{m};
  }
  EXPECT_TRUE(rig.carrier->sent.empty());
  EXPECT_EQ(rig.retrying->queued(), 3u);
  rig.carrier->fail_all = false;
  ASSERT_TRUE(rig.retrying->Publish(PduType::kConstruct, Bytes(4)).ok());
  EXPECT_EQ(rig.carrier->sent, (std::vector<FakeCarrier::Sent>{{PduType::kConstruct, 1},
                                                               {PduType::kConstruct, 2},
                                                               {PduType::kConstruct, 3},
                                                               {PduType::kConstruct, 4}}));
  const auto c = rig.retrying->counters();
  EXPECT_EQ(c.queued, 0u);
  EXPECT_EQ(c.retried, 3u);
  EXPECT_GE(c.failed_writes, 3u);
  EXPECT_EQ(c.given_up, 0u);
}

TEST(RetryingTransport, ALaterPublishWaitsBehindItsChannelsQueueEvenIfTheCarrierWouldTakeIt) {
  Rig rig;
  rig.carrier->fail_next = 1;
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(1)).ok());  // fails, queued
  rig.carrier->fail_next = 1;
  // The retry of 1 fails; 2 must not overtake it although the carrier would now take it.
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(2)).ok());
  EXPECT_TRUE(rig.carrier->sent.empty());
  EXPECT_EQ(rig.retrying->queued(), 2u);
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(3)).ok());
  EXPECT_EQ(rig.carrier->sent,
            (std::vector<FakeCarrier::Sent>{
                {PduType::kUpdate, 1}, {PduType::kUpdate, 2}, {PduType::kUpdate, 3}}));
}

TEST(RetryingTransport, AQueuedChannelDoesNotHoldBackAnother) {
  Rig rig;
  rig.carrier->failing = {PduType::kUpdate};
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(1)).ok());
  ASSERT_TRUE(rig.retrying->Publish(PduType::kMaxFeature, Bytes(2)).ok());
  EXPECT_EQ(rig.carrier->sent, (std::vector<FakeCarrier::Sent>{{PduType::kMaxFeature, 2}}));
  EXPECT_EQ(rig.retrying->queued(), 1u);
}

TEST(RetryingTransport, HandleTimeoutRetriesAndWaitsNoLongerThanTheRetryIntervalWhileQueued) {
  Rig rig;
  ASSERT_TRUE(rig.retrying->HandleTimeout(100).ok());
  rig.carrier->fail_all = true;
  ASSERT_TRUE(rig.retrying->Publish(PduType::kDestruct, Bytes(1)).ok());
  ASSERT_TRUE(rig.retrying->HandleTimeout(100).ok());
  EXPECT_EQ(rig.retrying->queued(), 1u);
  rig.carrier->fail_all = false;
  ASSERT_TRUE(rig.retrying->HandleTimeout(100).ok());
  EXPECT_EQ(rig.carrier->sent, (std::vector<FakeCarrier::Sent>{{PduType::kDestruct, 1}}));
  ASSERT_TRUE(rig.retrying->HandleTimeout(100).ok());
  // Nothing queued: the caller's wait; queued: at most the retry interval; sent before waiting.
  EXPECT_EQ(rig.carrier->waits_ms,
            (std::vector<int>{100, RetryingTransport::kRetryIntervalMs, 100, 100}));
  EXPECT_EQ(rig.retrying->counters().retried, 1u);
}

TEST(RetryingTransport, RefusesPastItsBoundWithAnErrorAndCountsIt) {
  Rig rig(3);
  rig.carrier->fail_all = true;
  for (uint8_t m = 1; m <= 3; ++m) {
    ASSERT_TRUE(rig.retrying->Publish(PduType::kPlayback, Bytes(m)).ok());
  }
  const Status refused = rig.retrying->Publish(PduType::kMaxFeature, Bytes(4));
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("3 PDUs already wait"), std::string::npos)
      << refused.error().message;
  EXPECT_NE(refused.error().message.find("Timeout"), std::string::npos) << refused.error().message;
  auto c = rig.retrying->counters();
  EXPECT_EQ(c.queued, 3u);
  EXPECT_EQ(c.given_up, 1u);
  // Once the carrier recovers, everything that was accepted goes, in order.
  rig.carrier->fail_all = false;
  EXPECT_EQ(rig.retrying->Flush(), 3u);
  EXPECT_EQ(rig.carrier->sent,
            (std::vector<FakeCarrier::Sent>{
                {PduType::kPlayback, 1}, {PduType::kPlayback, 2}, {PduType::kPlayback, 3}}));
  c = rig.retrying->counters();
  EXPECT_EQ(c.queued, 0u);
  EXPECT_EQ(c.retried, 3u);
  EXPECT_EQ(c.given_up, 1u);
}

TEST(RetryingTransport, DrainsALongQueueAtMostKMaxRetriesPerCallAtATime) {
  Rig rig;
  rig.carrier->fail_all = true;
  const size_t n = 2 * RetryingTransport::kMaxRetriesPerCall + 10;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(static_cast<uint8_t>(i))).ok());
  }
  rig.carrier->fail_all = false;
  EXPECT_EQ(rig.retrying->Flush(), RetryingTransport::kMaxRetriesPerCall);
  // A Publish behind a queue still waiting keeps its place.
  ASSERT_TRUE(rig.retrying->Publish(PduType::kUpdate, Bytes(255)).ok());
  EXPECT_EQ(rig.carrier->sent.size(), 2 * RetryingTransport::kMaxRetriesPerCall);
  EXPECT_EQ(rig.retrying->Flush(), 11u);
  ASSERT_EQ(rig.carrier->sent.size(), n + 1);
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(rig.carrier->sent[i].marker, static_cast<uint8_t>(i));
  EXPECT_EQ(rig.carrier->sent.back().marker, 255);
}

TEST(RetryingTransport, RefusesAnOversizedPduAtOnceWithoutQueueingIt) {
  Rig rig;
  rig.carrier->fail_all = true;
  EXPECT_FALSE(
      rig.retrying->Publish(PduType::kUpdate, std::vector<uint8_t>(kMaxPduBytes + 1)).ok());
  EXPECT_EQ(rig.retrying->queued(), 0u);
  EXPECT_EQ(rig.carrier->publish_calls, 0);
}

TEST(RetryingTransport, PassesSubscriptionsFdAndUrlThrough) {
  Rig rig;
  rig.retrying->Subscribe(PduType::kUpdate, [](std::span<const uint8_t>) {});
  EXPECT_EQ(rig.carrier->handlers[PduType::kUpdate].size(), 1u);
  EXPECT_EQ(rig.retrying->Fd(), 42);
  EXPECT_EQ(rig.retrying->Url(), "retrying+fake://");
  EXPECT_THROW(RetryingTransport(std::make_unique<FakeCarrier>(), 0), std::invalid_argument);
}

// A sender whose writes time out for 2 s of virtual time while it keeps publishing every 10 ms
// and handling in between: every PDU reaches the receiver once writes recover, in order.
TEST(RetryingTransport, NothingIsLostOverASimulatedWriteOutage) {
  SimNetwork net(11);
  const NodeAddress a{1, 1};
  const NodeAddress b{1, 2};
  RetryingTransport sender(net.Join(a, 1));
  auto receiver = net.Join(b, 1);
  std::vector<int64_t> got;
  receiver->Subscribe(PduType::kMaxFeature, [&](std::span<const uint8_t> bytes) {
    dtpdu::max_feature_t pdu;
    if (!DecodePdu(bytes, pdu)) got.push_back(pdu.sender_seq);
  });
  auto pdu = sample::MaxFeature();
  pdu.sender = ToPdu(a);
  net.BlockWrites(a, 2000);
  constexpr int64_t kCount = 300;
  size_t most_queued = 0;
  for (int64_t i = 1; i <= kCount; ++i) {
    pdu.sender_seq = i;
    ASSERT_TRUE(sender.Publish(PduType::kMaxFeature, EncodePdu(pdu)).ok()) << i;
    most_queued = std::max(most_queued, sender.queued());
    net.AdvanceMs(10);
    ASSERT_TRUE(sender.HandleTimeout(0).ok());
    ASSERT_TRUE(receiver->HandleTimeout(0).ok());
  }
  net.AdvanceMs(10);
  ASSERT_TRUE(receiver->HandleTimeout(0).ok());
  std::vector<int64_t> want;
  for (int64_t i = 1; i <= kCount; ++i) want.push_back(i);
  EXPECT_EQ(got, want);
  EXPECT_EQ(most_queued, 200u);  // 2000 ms of publishes every 10 ms
  // The 200 blocked ones, and the one published at 2000 ms behind what was still queued (a call
  // sends at most kMaxRetriesPerCall).
  EXPECT_EQ(sender.counters().retried, 201u);
  EXPECT_EQ(sender.counters().given_up, 0u);
  EXPECT_EQ(sender.queued(), 0u);
}

}  // namespace
}  // namespace dt
