// Round trips of every PDU over memq, udpm and DDS, exercise separation and bursts, inside a
// private network namespace the test makes for itself.
#include <chrono>
#include <functional>
#include <map>

#include <dds/dds.h>
#include <gtest/gtest.h>

#include "dt_pdu_dds.h"
#include "pdu/test/sample_pdus.h"
#include "transport/dds_codec.h"
#include "transport/dds_transport.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"
#include "transport/test/handle_until.h"
#include "transport/test/private_netns.h"

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
  c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
  c.deliver_own = true;  // memq has a single endpoint
  return c;
}

using testing::HandleUntil;

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
  ExpectRoundTrip(from, to, p.sender(), b, sample::VehicleState());
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

// Bytes after the LCM encoding (an authentication trailer) travel in the sample's `auth` member
// and come back appended, unchanged; more than the member holds, or bytes that are not a PDU of
// the channel's type, are refused by Publish.
TEST(DdsTypedTopics, CarryATrailerAfterThePduUnchangedAndRefuseWhatTheyCannotCarry) {
  SKIP_WITHOUT_NETNS();
  auto tx = MakeTransport(kDds, 4);
  auto rx = MakeTransport(kDds, 4);
  std::vector<std::vector<uint8_t>> got;
  rx->Subscribe(PduType::kMaxFeature,
                [&](std::span<const uint8_t> b) { got.emplace_back(b.begin(), b.end()); });
  AwaitReaders(*tx, PduType::kMaxFeature, 1);
  const std::vector<uint8_t> pdu = EncodePdu(sample::MaxFeature());
  std::vector<uint8_t> with_trailer = pdu;
  for (size_t i = 0; i < dds_codec::kMaxAuthBytes; ++i) {
    with_trailer.push_back(static_cast<uint8_t>(i * 7));
  }
  ASSERT_TRUE(tx->Publish(PduType::kMaxFeature, pdu).ok());
  ASSERT_TRUE(tx->Publish(PduType::kMaxFeature, with_trailer).ok());

  std::vector<uint8_t> too_long = with_trailer;
  too_long.push_back(0);
  const Status refused = tx->Publish(PduType::kMaxFeature, too_long);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("129 bytes follow the PDU"), std::string::npos)
      << refused.error().message;
  // A Playback's bytes are not a MaxFeature (LCM's fingerprint differs); a truncated PDU is none.
  EXPECT_FALSE(tx->Publish(PduType::kMaxFeature, EncodePdu(sample::Playback())).ok());
  EXPECT_FALSE(tx->Publish(PduType::kMaxFeature, std::span(pdu).first(pdu.size() - 1)).ok());

  ASSERT_TRUE(HandleUntil({rx.get()}, [&] { return got.size() >= 2; }));
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0], pdu);
  EXPECT_EQ(got[1], with_trailer);
}

// A batch published over DDS (its own topic, docs/pdu.md "Batch") arrives whole: every member, in
// the order published, its one authentication trailer verified, nothing refused.
TEST(DdsTypedTopics, ABatchArrivesWholeAndInOrder) {
  SKIP_WITHOUT_NETNS();
  constexpr uint8_t kExercise = 6;
  auto tx = MakeTransport(kDds, kExercise);
  auto rx = MakeTransport(kDds, kExercise);
  const auto key = std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x42));
  PduBusConfig from_config = Config({1, 1}, kExercise);
  from_config.auth.key = key;
  PduBusConfig to_config = Config({2, 2}, kExercise);
  to_config.auth.key = key;
  PduBus from(*tx, from_config);
  PduBus to(*rx, to_config);
  std::vector<int64_t> seqs;
  int reports = 0;
  to.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t& u) { seqs.push_back(u.sender_seq); });
  to.Subscribe<dtpdu::max_feature_t>([&](const dtpdu::max_feature_t& m) {
    seqs.push_back(m.sender_seq);
    ++reports;
  });
  AwaitReaders(*tx, PduType::kBatch, 1);
  constexpr int kPdus = 120;
  {
    PduBus::Batch batch(from);
    for (int i = 0; i < kPdus; ++i) {
      auto update = sample::Update();  // each its own feature and place, as a burst's
      update.feature_number += i;
      update.position_m[0] = 100.0 + 7.25 * i;
      const auto sent = i % 4 == 3 ? from.Publish(sample::MaxFeature()) : from.Publish(update);
      ASSERT_TRUE(sent.ok()) << sent.error().message;
    }
  }
  ASSERT_TRUE(HandleUntil({tx.get(), rx.get()}, [&] { return seqs.size() >= kPdus; }));
  ASSERT_EQ(seqs.size(), static_cast<size_t>(kPdus));
  for (int i = 0; i < kPdus; ++i) EXPECT_EQ(seqs[static_cast<size_t>(i)], i + 1);
  EXPECT_EQ(reports, kPdus / 4);
  EXPECT_GE(from.batches_sent(), 2u);  // 120 PDUs do not fit one 1400-byte datagram
  EXPECT_EQ(to.batches_received(), from.batches_sent());
  EXPECT_EQ(to.rejects().total(), 0u);
}

// A reader written against the generated C types alone (what any DDS tool with the IDL sees):
// named fields, and one instance per feature ID.
TEST(DdsTypedTopics, AnIndependentReaderSeesNamedFieldsAndOneInstancePerFeature) {
  SKIP_WITHOUT_NETNS();
  auto tx = MakeTransport(kDds, 5);
  const dds_entity_t participant = dds_create_participant(0, nullptr, nullptr);
  ASSERT_GT(participant, 0);
  const dds_entity_t topic =
      dds_create_topic(participant, &dtpdu_dds_update_t_desc,
                       ChannelName(5, PduType::kUpdate).c_str(), nullptr, nullptr);
  ASSERT_GT(topic, 0);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, 0);
  dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  ASSERT_GT(reader, 0);
  AwaitReaders(*tx, PduType::kUpdate, 1);

  auto pdu = sample::Update();  // feature 1:2:4
  std::vector<uint8_t> bytes = EncodePdu(pdu);
  bytes.push_back(0xEE);
  ASSERT_TRUE(tx->Publish(PduType::kUpdate, bytes).ok());
  pdu.change_seq += 1;  // a later change of the same feature
  ASSERT_TRUE(tx->Publish(PduType::kUpdate, EncodePdu(pdu)).ok());
  pdu.feature_number = 99;  // another feature
  ASSERT_TRUE(tx->Publish(PduType::kUpdate, EncodePdu(pdu)).ok());

  std::vector<dtpdu_dds_update_t> samples;
  std::vector<dds_instance_handle_t> instances;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (samples.size() < 3 && std::chrono::steady_clock::now() < deadline) {
    void* raw[4] = {};
    dds_sample_info_t infos[4];
    const dds_return_t n = dds_take(reader, raw, infos, 4, 4);
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      samples.push_back(*static_cast<const dtpdu_dds_update_t*>(raw[i]));
      instances.push_back(infos[i].instance_handle);
      // The copy keeps no pointers into the loan: only scalars are read below.
      samples.back().vertex_edits = {};
      samples.back().auth._length = static_cast<const dtpdu_dds_update_t*>(raw[i])->auth._length;
      samples.back().auth._buffer = nullptr;
    }
    if (n > 0) dds_return_loan(reader, raw, n);
    if (samples.size() < 3) {
      ASSERT_TRUE(tx->HandleTimeout(20).ok());
    }
  }
  dds_delete(participant);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[0].origin.site, 1);
  EXPECT_EQ(samples[0].origin.host, 2);
  EXPECT_EQ(samples[0].feature_number, 4);
  EXPECT_EQ(samples[0].header.exercise_id, sample::kSampleExercise);
  EXPECT_EQ(samples[0].change_seq, sample::Update().change_seq);
  EXPECT_EQ(samples[0].auth._length, 1u);  // the trailer byte
  EXPECT_EQ(samples[1].change_seq, sample::Update().change_seq + 1);
  EXPECT_EQ(samples[2].feature_number, 99);
  EXPECT_EQ(instances[0], instances[1]);
  EXPECT_NE(instances[0], instances[2]);
}

// With durable=1 a reader that joins after the features were published still gets the latest
// change of each (and only that), from the writer's history; MaxFeature stays volatile.
TEST(DdsTypedTopics, ADurableLateJoinerGetsTheLatestChangeOfEveryFeature) {
  SKIP_WITHOUT_NETNS();
  const std::string url = kDds + "&durable=1";
  auto holder = MakeTransport(url, 6);
  EXPECT_EQ(holder->Url(), url);
  auto pdu = sample::Update();
  for (int64_t feature = 1; feature <= 20; ++feature) {
    pdu.feature_number = feature;
    for (int64_t change = 1; change <= 3; ++change) {
      pdu.change_seq = feature * 10 + change;
      ASSERT_TRUE(holder->Publish(PduType::kUpdate, EncodePdu(pdu)).ok());
    }
  }
  ASSERT_TRUE(holder->Publish(PduType::kMaxFeature, EncodePdu(sample::MaxFeature())).ok());
  auto joiner = MakeTransport(url, 6);
  std::map<int64_t, std::vector<int64_t>> changes;  // feature -> change_seqs received
  int max_features = 0;
  joiner->Subscribe(PduType::kUpdate, [&](std::span<const uint8_t> b) {
    dtpdu::update_t got;
    if (!DecodePdu(b, got)) changes[got.feature_number].push_back(got.change_seq);
  });
  joiner->Subscribe(PduType::kMaxFeature, [&](std::span<const uint8_t>) { ++max_features; });
  ASSERT_TRUE(HandleUntil({joiner.get()}, [&] { return changes.size() >= 20; }));
  for (int64_t feature = 1; feature <= 20; ++feature) {
    EXPECT_EQ(changes[feature], (std::vector<int64_t>{feature * 10 + 3})) << feature;
  }
  EXPECT_EQ(max_features, 0);
}

TEST(DdsUrl, ParsesDomainAndConfig) {
  EXPECT_EQ(ParseDdsUrl("dds://").domain_id, 0u);
  EXPECT_EQ(ParseDdsUrl("dds://12").domain_id, 12u);
  EXPECT_EQ(ParseDdsUrl("dds://3?config=/x.xml").config_file, "/x.xml");
  EXPECT_THROW(ParseDdsUrl("dds://abc"), std::invalid_argument);
  EXPECT_THROW(ParseDdsUrl("dds://300"), std::invalid_argument);
  EXPECT_THROW(ParseDdsUrl("dds://1?cfg=x"), std::invalid_argument);
  EXPECT_FALSE(ParseDdsUrl("dds://3?config=/x.xml").durable_features);
  EXPECT_TRUE(ParseDdsUrl("dds://3?config=/x.xml&durable=1").durable_features);
  EXPECT_EQ(ParseDdsUrl("dds://3?durable=1&config=/x.xml").config_file, "/x.xml");
  EXPECT_THROW(ParseDdsUrl("dds://1?durable=yes"), std::invalid_argument);
  EXPECT_THROW(ParseDdsUrl("dds://1?config=/x.xml&"), std::invalid_argument);
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
