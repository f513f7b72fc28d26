// Tests batches on a PduBus over memq: a tick's PDUs packed into few datagrams, a lone PDU sent as
// itself, a batch taken whole or refused whole, one trailer per datagram, and a sender of another
// protocol version refused and named.
#include <gtest/gtest.h>

#include "pdu/batch.h"
#include "pdu/test/sample_pdus.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"

namespace dt {
namespace {

PduBusConfig Config(NodeAddress local, bool deliver_own) {
  PduBusConfig c;
  c.exercise_id = sample::kSampleExercise;
  c.local = local;
  c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
  c.deliver_own = deliver_own;
  return c;
}

// Datagrams seen on each channel, and their largest size.
struct Wire {
  explicit Wire(Transport& t) {
    for (PduType type : kAllPduTypes) {
      t.Subscribe(type, [this, type](std::span<const uint8_t> bytes) {
        ++datagrams[type];
        largest = std::max(largest, bytes.size());
      });
    }
  }
  std::map<PduType, int> datagrams;
  size_t largest = 0;
};

// The sample Update moved to feature i's place: a member differing from the one before it in a
// few fields, as a burst's are.
dtpdu::update_t UpdateOf(int i) {
  auto u = sample::Update();
  u.feature_number += i;
  u.position_m[0] = 100.0 + 7.25 * (i % 100);
  u.position_m[2] = 100.0 + 5.5 * (i / 100);
  return u;
}

TEST(PduBatch, ATicksPdusLeavePackedInFewDatagramsAndArriveInOrder) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Wire wire(t);
  PduBusConfig config = Config({1, 2}, /*deliver_own=*/true);
  config.flight_datagrams = 2;  // so that some leave before the tick ends
  PduBus bus(t, config);
  std::vector<int64_t> seqs;
  bus.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t& u) { seqs.push_back(u.sender_seq); });
  bus.Subscribe<dtpdu::destruct_t>(
      [&](const dtpdu::destruct_t& d) { seqs.push_back(d.sender_seq); });
  constexpr int kPdus = 300;
  {
    PduBus::Batch batch(bus);
    for (int i = 0; i < kPdus; ++i) {
      if (i % 5 == 4) {
        ASSERT_TRUE(bus.Publish(sample::Destruct()).ok());
      } else {
        ASSERT_TRUE(bus.Publish(UpdateOf(i)).ok());
      }
    }
    // Full datagrams leave two at a time; the rest waits for the end of the tick.
    ASSERT_TRUE(bus.HandleTimeout(0).ok());
    EXPECT_LT(seqs.size(), static_cast<size_t>(kPdus));
    EXPECT_GT(seqs.size(), 0u);
    EXPECT_EQ(wire.datagrams[PduType::kBatch] % 2, 0);
  }
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  ASSERT_EQ(seqs.size(), static_cast<size_t>(kPdus));
  for (int i = 0; i < kPdus; ++i) EXPECT_EQ(seqs[i], i + 1);
  const size_t update_bytes = EncodePdu(sample::Update()).size();
  const size_t whole_per_datagram =
      (kMaxPduBytes - kBatchBaseBytes) / (update_bytes + kBatchMemberBytes);
  // Members behind another go as deltas: well under a third of the datagrams whole ones take.
  EXPECT_LE(wire.datagrams[PduType::kBatch], static_cast<int>(kPdus / whole_per_datagram + 1) / 3);
  EXPECT_GE(wire.datagrams[PduType::kBatch], 3);
  EXPECT_EQ(wire.datagrams[PduType::kUpdate] + wire.datagrams[PduType::kDestruct], 0);
  EXPECT_LE(wire.largest, kMaxPduBytes);
  EXPECT_EQ(bus.batches_sent(), static_cast<uint64_t>(wire.datagrams[PduType::kBatch]));
  EXPECT_EQ(bus.batches_received(), bus.batches_sent());
}

// With the default flight, a tick of a few datagrams leaves whole at its end, in order, and
// the next tick's PDUs follow it.
TEST(PduBatch, ATicksFullDatagramsWaitForItsEndInAFlight) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Wire wire(t);
  PduBus bus(t, Config({1, 2}, /*deliver_own=*/true));
  ASSERT_GE(bus.config().flight_datagrams, 8);
  std::vector<int64_t> seqs;
  bus.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t& u) { seqs.push_back(u.sender_seq); });
  constexpr int kPdus = 200;  // several datagrams
  for (int tick = 0; tick < 2; ++tick) {
    const int sent_before = wire.datagrams[PduType::kBatch];
    {
      PduBus::Batch batch(bus);
      for (int i = 0; i < kPdus; ++i) ASSERT_TRUE(bus.Publish(UpdateOf(i)).ok());
      ASSERT_TRUE(bus.HandleTimeout(0).ok());
      EXPECT_EQ(seqs.size(), static_cast<size_t>(tick * kPdus)) << "tick " << tick;
      EXPECT_EQ(wire.datagrams[PduType::kBatch], sent_before) << "tick " << tick;
    }
    ASSERT_TRUE(bus.HandleTimeout(0).ok());
    ASSERT_EQ(seqs.size(), static_cast<size_t>((tick + 1) * kPdus));
  }
  for (int i = 0; i < 2 * kPdus; ++i) EXPECT_EQ(seqs[i], i + 1);
  EXPECT_GE(wire.datagrams[PduType::kBatch], 2 * 3);
  EXPECT_EQ(bus.batches_sent(), static_cast<uint64_t>(wire.datagrams[PduType::kBatch]));
}

TEST(PduBatch, AFlightOfNoDatagramIsRefused) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBusConfig config = Config({1, 2}, /*deliver_own=*/true);
  config.flight_datagrams = 0;
  try {
    PduBus bus(t, config);
    FAIL() << "a flight of 0 datagrams was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("flight_datagrams = 0"), std::string::npos) << e.what();
  }
}

TEST(PduBatch, ALonePduLeavesAsItselfAtTheEndOfItsTick) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Wire wire(t);
  PduBus bus(t, Config({1, 2}, /*deliver_own=*/true));
  int got = 0;
  bus.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t&) { ++got; });
  {
    PduBus::Batch batch(bus);
    ASSERT_TRUE(bus.Publish(sample::Update()).ok());
  }
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  EXPECT_EQ(got, 1);
  EXPECT_EQ(wire.datagrams[PduType::kUpdate], 1);
  EXPECT_EQ(wire.datagrams[PduType::kBatch], 0);
}

TEST(PduBatch, WithoutBatchingEveryPduGoesAlone) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Wire wire(t);
  PduBusConfig c = Config({1, 2}, /*deliver_own=*/true);
  c.batch = false;
  PduBus bus(t, c);
  {
    PduBus::Batch batch(bus);
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(bus.Publish(sample::Update()).ok());
  }
  ASSERT_TRUE(bus.HandleTimeout(0).ok());
  EXPECT_EQ(wire.datagrams[PduType::kUpdate], 3);
  EXPECT_EQ(wire.datagrams[PduType::kBatch], 0);
}

// A batch from 1:2 (the samples' sender) of these members, published raw.
std::vector<uint8_t> RawBatch(const std::vector<std::pair<PduType, std::vector<uint8_t>>>& m,
                              NodeAddress sender = {1, 2}) {
  std::vector<BatchMember> members;
  for (const auto& [type, bytes] : m) members.push_back({type, bytes});
  std::vector<uint8_t> out;
  EncodeBatchInto(sample::kSampleExercise, 1, sender, members, out);
  return out;
}

struct Receiver {
  explicit Receiver(Transport& t) : bus(t, Config({9, 9}, /*deliver_own=*/false)) {
    bus.Subscribe<dtpdu::update_t>([this](const dtpdu::update_t&) { ++got; });
    bus.Subscribe<dtpdu::construct_t>([this](const dtpdu::construct_t&) { ++got; });
    bus.Subscribe<dtpdu::destruct_t>([this](const dtpdu::destruct_t&) { ++got; });
  }
  PduBus bus;
  int got = 0;
};

TEST(PduBatch, AGoodBatchIsTakenWhole) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Receiver r(t);
  ASSERT_TRUE(
      t.Publish(PduType::kBatch, RawBatch({{PduType::kUpdate, EncodePdu(sample::Update())},
                                           {PduType::kConstruct, EncodePdu(sample::Construct())}}))
          .ok());
  ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
  EXPECT_EQ(r.got, 2);
  EXPECT_EQ(r.bus.rejects().total(), 0u);
}

TEST(PduBatch, ABatchWithOneBadMemberIsRefusedWholeAndCounted) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Receiver r(t);
  auto bad = sample::Construct();
  bad.length_m[0] = -1;  // out_of_range
  auto stranger = sample::Destruct();
  stranger.sender.host = 3;  // not the batch's sender
  auto nested = RawBatch({{PduType::kUpdate, EncodePdu(sample::Update())}});
  const auto good = EncodePdu(sample::Update());
  for (const auto& [member, reason] :
       std::vector<std::pair<std::pair<PduType, std::vector<uint8_t>>, RejectReason>>{
           {{PduType::kConstruct, EncodePdu(bad)}, RejectReason::kOutOfRange},
           {{PduType::kDestruct, EncodePdu(stranger)}, RejectReason::kSenderMismatch},
           {{PduType::kBatch, nested}, RejectReason::kUnknownPduType},
           {{PduType::kDestruct, EncodePdu(sample::Update())}, RejectReason::kWrongFingerprint},
       }) {
    const uint64_t before = r.bus.rejects().count(reason);
    ASSERT_TRUE(t.Publish(PduType::kBatch,
                          RawBatch({{PduType::kUpdate, good}, member, {PduType::kUpdate, good}}))
                    .ok());
    ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
    EXPECT_EQ(r.got, 0) << RejectReasonName(reason);
    EXPECT_EQ(r.bus.rejects().count(reason), before + 1) << RejectReasonName(reason);
  }
  EXPECT_EQ(r.bus.accepted(), 0u);
  EXPECT_EQ(r.bus.batches_received(), 0u);
}

TEST(PduBatch, OneTrailerPerDatagramAndATamperedBatchIsRefusedWhole) {
  LcmTransport t("memq://", sample::kSampleExercise);
  auto key = std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 7));
  PduBusConfig sc = Config({1, 2}, false);
  sc.auth.key = key;
  PduBus sender(t, sc);
  PduBusConfig rc = Config({9, 9}, false);
  rc.auth.key = key;
  PduBus receiver(t, rc);
  int got = 0;
  receiver.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t&) { ++got; });
  std::vector<std::vector<uint8_t>> datagrams;
  t.Subscribe(PduType::kBatch,
              [&](std::span<const uint8_t> b) { datagrams.emplace_back(b.begin(), b.end()); });
  {
    PduBus::Batch batch(sender);
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(sender.Publish(sample::Update()).ok());
  }
  ASSERT_TRUE(receiver.HandleTimeout(0).ok());
  EXPECT_EQ(got, 5);
  ASSERT_EQ(datagrams.size(), 1u);
  ASSERT_NE(sender.authenticator(), nullptr);
  EXPECT_EQ(sender.authenticator()->last_sequence(), 1u);  // one trailer for five PDUs
  // The same datagram with one byte of a member changed: refused whole by its MAC.
  std::vector<uint8_t> tampered = datagrams[0];
  tampered[kBatchBaseBytes + kBatchMemberBytes + 40] ^= 1;
  ASSERT_TRUE(t.Publish(PduType::kBatch, tampered).ok());
  ASSERT_TRUE(receiver.HandleTimeout(0).ok());
  EXPECT_EQ(got, 5);
  EXPECT_EQ(receiver.rejects().count(RejectReason::kBadMac), 1u);
}

// What a receiver hands on from deltas is what was published: every field of every member.
TEST(PduBatch, MembersSentAsDeltasArriveAsPublished) {
  LcmTransport t("memq://", sample::kSampleExercise);
  std::vector<std::vector<uint8_t>> datagrams;
  t.Subscribe(PduType::kBatch,
              [&](std::span<const uint8_t> b) { datagrams.emplace_back(b.begin(), b.end()); });
  PduBus sender(t, Config({1, 2}, /*deliver_own=*/false));
  Receiver r(t);
  std::vector<std::vector<uint8_t>> got;
  r.bus.Subscribe<dtpdu::update_t>([&](const dtpdu::update_t& u) { got.push_back(EncodePdu(u)); });
  std::vector<std::vector<uint8_t>> sent;
  {
    PduBus::Batch batch(sender);
    for (int i = 0; i < 100; ++i) {
      auto u = UpdateOf(i);
      auto seq = sender.Publish(u);
      ASSERT_TRUE(seq.ok());
      u.sender_seq = seq.value();
      u.header.timestamp_dis = sender.config().clock();  // the bus stamps both
      sent.push_back(EncodePdu(u));
    }
  }
  ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
  ASSERT_EQ(got.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i) {
    // The clock may tick between publishing and this copy: compare past the header.
    EXPECT_EQ(std::vector<uint8_t>(got[i].begin() + 8 + 7, got[i].end()),
              std::vector<uint8_t>(sent[i].begin() + 8 + 7, sent[i].end()))
        << i;
  }
  ASSERT_GE(datagrams.size(), 2u);
  // Each datagram's first member whole, the rest as deltas.
  for (const auto& d : datagrams) {
    dtpdu::batch_t b;
    ASSERT_FALSE(DecodePdu(d, b));
    ASSERT_GE(b.members.size(), 2u);
    EXPECT_EQ(b.members[0].encoding, static_cast<uint8_t>(MemberEncoding::kWhole));
    for (size_t k = 1; k < b.members.size(); ++k) {
      EXPECT_EQ(b.members[k].encoding, static_cast<uint8_t>(MemberEncoding::kDelta)) << k;
    }
  }
}

TEST(PduBatch, ASenderOfThePreviousProtocolVersionIsRefusedAndNamedOnce) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Receiver r(t);
  auto old = sample::Update();
  old.header.protocol_version = kProtocolVersion - 1;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(t.Publish(PduType::kUpdate, EncodePdu(old)).ok());
  ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
  EXPECT_EQ(r.got, 0);
  EXPECT_EQ(r.bus.rejects().count(RejectReason::kWrongProtocolVersion), 3u);
  EXPECT_EQ(r.bus.wrong_protocol_senders(), (std::set<NodeAddress>{{1, 2}}));
  dtpdu::update_t decoded;
  auto rej = DecodeAndValidate(EncodePdu(old), sample::Context(), decoded);
  ASSERT_TRUE(rej.has_value());
  EXPECT_NE(rej->detail.find(fmt::format("wire format {}", kProtocolVersion - 1)),
            std::string::npos)
      << rej->detail;
  EXPECT_NE(rej->detail.find("another release"), std::string::npos) << rej->detail;
}

// A flood of old-version PDUs naming ever new senders is refused and counted whole, but only the
// first kMaxWrongProtocolSenders senders are kept and named.
TEST(PduBatch, ManySendersOfAnotherVersionAreCountedButNamedUpToACap) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Receiver r(t);
  constexpr size_t kSenders = PduBus::kMaxWrongProtocolSenders + 100;
  for (size_t i = 0; i < kSenders; ++i) {
    auto old = sample::Update();
    old.header.protocol_version = kProtocolVersion - 1;
    old.sender.host = static_cast<int16_t>(1000 + i);
    ASSERT_TRUE(t.Publish(PduType::kUpdate, EncodePdu(old)).ok());
  }
  ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
  EXPECT_EQ(r.got, 0);
  EXPECT_EQ(r.bus.rejects().count(RejectReason::kWrongProtocolVersion), kSenders);
  EXPECT_EQ(r.bus.wrong_protocol_senders().size(), PduBus::kMaxWrongProtocolSenders);
  EXPECT_EQ(*r.bus.wrong_protocol_senders().begin(), (NodeAddress{1, 1000}));
}

// A version 3 process's batch: members without an encoding, so batch_t's fingerprint of then.
// Refused as the previous protocol, by the version its header names, not as an unknown type.
TEST(PduBatch, ABatchOfTheVersion3LayoutIsRefusedAsThePreviousProtocol) {
  LcmTransport t("memq://", sample::kSampleExercise);
  Receiver r(t);
  const auto update = EncodePdu(sample::Update());
  std::vector<uint8_t> old = {0xca, 0xc4, 0x29, 0xc5, 0xb2, 0x1f, 0xf2, 0x65};  // its fingerprint
  old.insert(old.end(), {3, sample::kSampleExercise, 231, 0, 0, 0, 1});         // header
  old.insert(old.end(), {0, 1, 0, 2, 0, 1});  // sender 1:2, one member
  old.push_back(221);                         // pdu_type, then num_bytes and bytes
  old.push_back(static_cast<uint8_t>(update.size() >> 8));
  old.push_back(static_cast<uint8_t>(update.size()));
  old.insert(old.end(), update.begin(), update.end());
  ASSERT_TRUE(t.Publish(PduType::kBatch, old).ok());
  ASSERT_TRUE(r.bus.HandleTimeout(0).ok());
  EXPECT_EQ(r.got, 0);
  EXPECT_EQ(r.bus.rejects().count(RejectReason::kWrongProtocolVersion), 1u);
  EXPECT_EQ(r.bus.wrong_protocol_senders(), (std::set<NodeAddress>{{1, 2}}));
  std::vector<MemberPdu> members;
  auto rej = DecodeBatch(old, sample::Context(), members);
  ASSERT_TRUE(rej.has_value());
  EXPECT_NE(rej->detail.find("wire format 3"), std::string::npos) << rej->detail;
}

}  // namespace
}  // namespace dt
