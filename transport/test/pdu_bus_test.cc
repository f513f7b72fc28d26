// Tests PduBus over memq: typed round trips, stamping, echo suppression, and that handlers never
// see a rejected PDU.
#include "transport/pdu_bus.h"

#include <gtest/gtest.h>

#include "pdu/test/sample_pdus.h"
#include "transport/lcm_transport.h"

namespace dt {
namespace {

PduBusConfig Config(NodeAddress local, bool deliver_own = true) {
  PduBusConfig c;
  c.exercise_id = sample::kSampleExercise;
  c.local = local;
  c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
  c.deliver_own = deliver_own;
  c.clock = [] { return 0xABCDEF01u; };
  return c;
}

template <typename Pdu>
void ExpectRoundTrip(PduBus& bus, const Pdu& sent) {
  std::vector<Pdu> got;
  bus.Subscribe<Pdu>([&](const Pdu& p) { got.push_back(p); });
  auto seq = bus.Publish(sent);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  ASSERT_EQ(got.size(), 1u);
  Pdu expected = sent;
  expected.header.timestamp_dis = static_cast<int32_t>(0xABCDEF01u);
  expected.sender = ToPdu(bus.config().local);
  expected.sender_seq = seq.value();
  EXPECT_EQ(EncodePdu(got[0]), EncodePdu(expected));
}

TEST(PduBus, EveryTypeRoundTripsOverMemq) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBus bus(t, Config({9, 9}));
  ExpectRoundTrip(bus, sample::Construct());
  ExpectRoundTrip(bus, sample::Update());
  ExpectRoundTrip(bus, sample::Destruct());
  ExpectRoundTrip(bus, sample::MaxFeature());
  ExpectRoundTrip(bus, sample::Playback());
  ExpectRoundTrip(bus, sample::AntiEntropySummary());
  EXPECT_EQ(bus.last_sender_seq(), 6);
  EXPECT_EQ(bus.accepted(), 6u);
}

TEST(PduBus, DropsItsOwnEchoUnlessAsked) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBus bus(t, Config({9, 9}, /*deliver_own=*/false));
  int got = 0;
  bus.Subscribe<dtpdu::destruct_t>([&](const dtpdu::destruct_t&) { ++got; });
  ASSERT_TRUE(bus.Publish(sample::Destruct()).ok());
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  EXPECT_EQ(got, 0);
  EXPECT_EQ(bus.own_echoes(), 1u);
}

TEST(PduBus, RefusesToSendAnInvalidPdu) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBus bus(t, Config({9, 9}));
  int raw = 0;
  t.Subscribe(PduType::kConstruct, [&](std::span<const uint8_t>) { ++raw; });
  auto pdu = sample::Construct();
  pdu.length_m[0] = -1;
  auto r = bus.Publish(pdu);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("out_of_range"), std::string::npos) << r.error().message;
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  EXPECT_EQ(raw, 0);
  EXPECT_EQ(bus.last_sender_seq(), 0);
}

TEST(PduBus, HandlersNeverSeeRejectedPdus) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBus bus(t, Config({9, 9}));
  int got = 0;
  bus.Subscribe<dtpdu::construct_t>([&](const dtpdu::construct_t&) { ++got; });
  auto bad = sample::Construct();
  bad.position_m[0] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(t.Publish(PduType::kConstruct, EncodePdu(bad)).ok());
  auto foreign = sample::Construct();
  foreign.header.exercise_id = 99;
  ASSERT_TRUE(t.Publish(PduType::kConstruct, EncodePdu(foreign)).ok());
  ASSERT_TRUE(t.Publish(PduType::kConstruct, std::vector<uint8_t>{1, 2, 3}).ok());
  ASSERT_TRUE(t.Publish(PduType::kConstruct, EncodePdu(sample::Construct())).ok());
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  EXPECT_EQ(got, 1);
  EXPECT_EQ(bus.rejects().count(RejectReason::kNotFinite), 1u);
  EXPECT_EQ(bus.rejects().count(RejectReason::kForeignExercise), 1u);
  EXPECT_EQ(bus.rejects().count(RejectReason::kTruncated), 1u);
  EXPECT_EQ(bus.rejects().total(), 3u);
}

TEST(PduBus, RefusesABadConfiguration) {
  LcmTransport t("memq://", 1);
  PduBusConfig c = Config({1, 1});
  c.terrain_size_x_m = c.terrain_size_z_m = 0;
  EXPECT_THROW(PduBus(t, c), std::invalid_argument);
  c.terrain_size_x_m = c.terrain_size_z_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(PduBus(t, c), std::invalid_argument);
  c.terrain_size_x_m = 100;  // each side is checked
  EXPECT_THROW(PduBus(t, c), std::invalid_argument);
  c.terrain_size_x_m = std::numeric_limits<double>::quiet_NaN();
  c.terrain_size_z_m = 100;
  EXPECT_THROW(PduBus(t, c), std::invalid_argument);
}

}  // namespace
}  // namespace dt
