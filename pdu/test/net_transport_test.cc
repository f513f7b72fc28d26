// Round trips of every PDU over memq, udpm and DDS, exercise separation and bursts, inside a
// private network namespace the test makes for itself.
#include <chrono>
#include <functional>

#include <gtest/gtest.h>

#include "pdu/dds_transport.h"
#include "pdu/lcm_transport.h"
#include "pdu/pdu_bus.h"
#include "pdu/test/private_netns.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

constexpr const char* kUdpm = "udpm://239.255.76.67:7667?ttl=0";
const std::string kDds =
    std::string("dds://0?config=") + DT_SOURCE_DIR + "/configs/cyclonedds-loopback.xml";

#define SKIP_WITHOUT_NETNS()                                               \
  do {                                                                     \
    if (auto reason = testing::NetnsSkipReason()) GTEST_SKIP() << *reason; \
  } while (0)

PduBusConfig Config(NodeAddress local, uint8_t exercise = sample::kSampleExercise) {
  PduBusConfig c;
  c.exercise_id = exercise;
  c.local = local;
  c.terrain_size_m = sample::kSampleTerrainM;
  c.deliver_own = true;  // memq has a single endpoint
  return c;
}

// Handles until done() or 10 s pass; returns done().
bool HandleUntil(std::initializer_list<Transport*> transports, const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    for (Transport* t : transports) {
      if (!t->HandleTimeout(20).ok()) return false;
    }
  }
  return done();
}

// A sender and a receiver on one carrier; for memq they are the same object.
struct Pair {
  std::unique_ptr<Transport> a;
  std::unique_ptr<Transport> b;
  Transport& sender() { return *a; }
  Transport& receiver() { return b ? *b : *a; }
};

Pair MakePair(const std::string& url, uint8_t exercise_a = sample::kSampleExercise,
              uint8_t exercise_b = sample::kSampleExercise) {
  Pair p;
  p.a = MakeTransport(url, exercise_a);
  if (url != "memq://") p.b = MakeTransport(url, exercise_b);
  return p;
}

// DDS delivers volatile data only to matched readers: wait for them before sending.
void AwaitReaders(Transport& sender, PduType type, int readers) {
  if (auto* dds = dynamic_cast<DdsTransport*>(&sender)) {
    ASSERT_TRUE(dds->WaitForReaders(type, readers, 10000)) << PduTypeName(type);
  }
}

template <typename Pdu>
void ExpectRoundTrip(PduBus& from, PduBus& to, Transport& a, Transport& b, const Pdu& pdu) {
  std::vector<std::vector<uint8_t>> got;
  to.Subscribe<Pdu>([&](const Pdu& p) { got.push_back(EncodePdu(p)); });
  AwaitReaders(a, PduTraits<Pdu>::kType, 1);
  auto seq = from.Publish(pdu);
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  ASSERT_TRUE(HandleUntil({&a, &b}, [&] { return !got.empty(); }))
      << PduTypeName(PduTraits<Pdu>::kType) << " never arrived";
  Pdu sent_copy;
  ASSERT_EQ(DecodePdu(got[0], sent_copy), std::nullopt);
  // Everything but the stamping the bus does must arrive as sent.
  EXPECT_EQ(sent_copy.header.pdu_type, static_cast<uint8_t>(PduTraits<Pdu>::kType));
  EXPECT_EQ(sent_copy.sender_seq, seq.value());
  sent_copy.header = pdu.header;
  sent_copy.sender = pdu.sender;
  sent_copy.sender_seq = pdu.sender_seq;
  EXPECT_EQ(EncodePdu(sent_copy), EncodePdu(pdu));
  EXPECT_EQ(got.size(), 1u);
}

class EveryCarrier : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryCarrier, EveryPduTypeRoundTrips) {
  SKIP_WITHOUT_NETNS();
  Pair p = MakePair(GetParam());
  PduBus from(p.sender(), Config({1, 1}));
  PduBus to(p.receiver(), Config({2, 2}));
  Transport& b = p.receiver();
  ExpectRoundTrip(from, to, p.sender(), b, sample::Construct());
  ExpectRoundTrip(from, to, p.sender(), b, sample::Update());
  ExpectRoundTrip(from, to, p.sender(), b, sample::Destruct());
  ExpectRoundTrip(from, to, p.sender(), b, sample::MaxFeature());
  ExpectRoundTrip(from, to, p.sender(), b, sample::Playback());
  ExpectRoundTrip(from, to, p.sender(), b, sample::AntiEntropySummary());
  EXPECT_EQ(to.rejects().total(), 0u);
}

TEST_P(EveryCarrier, RefusesMoreThanOneDatagram) {
  SKIP_WITHOUT_NETNS();
  Pair p = MakePair(GetParam());
  EXPECT_FALSE(p.sender().Publish(PduType::kUpdate, std::vector<uint8_t>(kMaxPduBytes + 1)).ok());
}

INSTANTIATE_TEST_SUITE_P(Carriers, EveryCarrier, ::testing::Values("memq://", kUdpm, kDds),
                         [](const auto& param_info) {
                           return param_info.param.substr(0, param_info.param.find(':'));
                         });

class RealCarrier : public ::testing::TestWithParam<std::string> {};

TEST_P(RealCarrier, TwoExercisesOnOneHostNeverSeeEachOther) {
  SKIP_WITHOUT_NETNS();
  auto one_tx = MakeTransport(GetParam(), 1);
  auto one_rx = MakeTransport(GetParam(), 1);
  auto two_rx = MakeTransport(GetParam(), 2);
  auto two_tx = MakeTransport(GetParam(), 2);
  int one = 0;
  std::vector<int64_t> two;  // sender_seq of what exercise 2 received
  one_rx->Subscribe(PduType::kDestruct, [&](std::span<const uint8_t>) { ++one; });
  two_rx->Subscribe(PduType::kDestruct, [&](std::span<const uint8_t> b) {
    dtpdu::destruct_t pdu;
    if (!DecodePdu(b, pdu)) two.push_back(pdu.sender_seq);
  });
  AwaitReaders(*one_tx, PduType::kDestruct, 1);
  AwaitReaders(*two_tx, PduType::kDestruct, 1);
  auto pdu = sample::Destruct();
  ASSERT_TRUE(one_tx->Publish(PduType::kDestruct, EncodePdu(pdu)).ok());
  ASSERT_TRUE(one_tx->Publish(PduType::kDestruct, EncodePdu(pdu)).ok());
  // Exercise 2's marker is sent after exercise 1's traffic: once it is handled, anything that
  // leaked across would have been handled before it.
  pdu.sender_seq = 99;
  ASSERT_TRUE(two_tx->Publish(PduType::kDestruct, EncodePdu(pdu)).ok());
  ASSERT_TRUE(HandleUntil({one_rx.get(), two_rx.get()}, [&] { return one == 2 && !two.empty(); }));
  EXPECT_EQ(one, 2);
  EXPECT_EQ(two, (std::vector<int64_t>{99}));
}

TEST_P(RealCarrier, ABurstOfFiveThousandArrivesWhole) {
  SKIP_WITHOUT_NETNS();
  auto tx = MakeTransport(GetParam(), 3);
  auto rx = MakeTransport(GetParam(), 3);
  int64_t received = 0;
  rx->Subscribe(PduType::kUpdate, [&](std::span<const uint8_t>) { ++received; });
  AwaitReaders(*tx, PduType::kUpdate, 1);
  const auto bytes = EncodePdu(sample::Update());
  for (int i = 0; i < 5000; ++i) ASSERT_TRUE(tx->Publish(PduType::kUpdate, bytes).ok());
  EXPECT_TRUE(HandleUntil({rx.get()}, [&] { return received >= 5000; }));
  EXPECT_EQ(received, 5000);
}

INSTANTIATE_TEST_SUITE_P(Carriers, RealCarrier, ::testing::Values(kUdpm, kDds),
                         [](const auto& param_info) {
                           return param_info.param.substr(0, param_info.param.find(':'));
                         });

TEST(LcmTransportUdpm, AsksForATwoMebibyteReceiveBuffer) {
  SKIP_WITHOUT_NETNS();
  LcmTransport t(kUdpm, 1);
  EXPECT_EQ(t.lcm_url(), std::string(kUdpm) + "&recv_buf_size=2097152");
  LcmTransport own("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304", 1);
  EXPECT_EQ(own.lcm_url(), "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
}

TEST(DdsUrl, ParsesDomainAndConfig) {
  EXPECT_EQ(ParseDdsUrl("dds://").domain_id, 0u);
  EXPECT_EQ(ParseDdsUrl("dds://12").domain_id, 12u);
  EXPECT_EQ(ParseDdsUrl("dds://3?config=/x.xml").config_file, "/x.xml");
  EXPECT_THROW(ParseDdsUrl("dds://abc"), std::invalid_argument);
  EXPECT_THROW(ParseDdsUrl("dds://300"), std::invalid_argument);
  EXPECT_THROW(ParseDdsUrl("dds://1?cfg=x"), std::invalid_argument);
  EXPECT_THROW(MakeTransport("dds://1?config=/nonexistent.xml", 1), std::runtime_error);
}

}  // namespace
}  // namespace dt

int main(int argc, char** argv) {
  dt::testing::EnterPrivateNetns(argc, argv);
  if (auto reason = dt::testing::NetnsSkipReason()) {
    std::fprintf(stderr, "network tests skipped: %s\n", reason->c_str());
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
