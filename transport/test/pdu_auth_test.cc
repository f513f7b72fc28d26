// Tests PDU authentication through PduBus over memq: authentic PDUs are accepted, and each drop
// reason (unauthenticated, bad_mac, sender_mismatch, replayed, stale) is counted and never
// reaches a handler.
#include "pdu/pdu_auth.h"

#include <gtest/gtest.h>
#include <sodium.h>

#include <cmath>
#include <random>
#include <set>

#include "pdu/test/sample_pdus.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"

namespace dt {
namespace {

constexpr int64_t kStartMs = 1'700'000'000'000;  // a wall-clock time, ms since the epoch

std::shared_ptr<const ExerciseKey> Key(uint8_t fill) {
  return std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, fill));
}

PduAuthConfig Auth(std::shared_ptr<const ExerciseKey> key, const int64_t* now_ms,
                   uint64_t incarnation = 0) {
  PduAuthConfig a;
  a.key = std::move(key);
  a.wall_clock_ms = [now_ms] { return *now_ms; };
  a.incarnation = incarnation;
  return a;
}

PduBusConfig Config(NodeAddress local, PduAuthConfig auth) {
  PduBusConfig c;
  c.exercise_id = sample::kSampleExercise;
  c.local = local;
  c.terrain_size_x_m = c.terrain_size_z_m = sample::kSampleTerrainM;
  c.auth = std::move(auth);
  return c;
}

// A receiving bus (2:2) on memq with the exercise key, counting the Constructs it is handed;
// raw bytes are injected on the Construct channel as another program on the group would.
class AuthTest : public ::testing::Test {
 protected:
  AuthTest() : bus_(transport_, Config({2, 2}, Auth(key_, &now_ms_))) {
    bus_.Subscribe<dtpdu::construct_t>([this](const dtpdu::construct_t&) { ++handled_; });
  }

  // The sample Construct (sender 1:2) signed by an authenticator of `signer` with `key`.
  std::vector<uint8_t> Signed(PduAuthenticator& signer,
                              dtpdu::construct_t pdu = sample::Construct()) {
    std::vector<uint8_t> bytes = EncodePdu(pdu);
    signer.Sign(bytes);
    return bytes;
  }

  void Inject(const std::vector<uint8_t>& bytes) {
    ASSERT_TRUE(transport_.Publish(PduType::kConstruct, bytes).ok());
    ASSERT_TRUE(bus_.HandleTimeout(0).ok());
  }

  uint64_t count(RejectReason r) const { return bus_.rejects().count(r); }

  int64_t now_ms_ = kStartMs;
  std::shared_ptr<const ExerciseKey> key_ = Key(0x11);
  LcmTransport transport_{"memq://", sample::kSampleExercise};
  PduBus bus_;
  int handled_ = 0;
};

TEST_F(AuthTest, AcceptsAPduFromAnotherBusWithTheKey) {
  std::vector<std::vector<uint8_t>> wire;
  transport_.Subscribe(PduType::kConstruct,
                       [&](std::span<const uint8_t> b) { wire.emplace_back(b.begin(), b.end()); });
  PduBus sender(transport_, Config({1, 2}, Auth(key_, &now_ms_)));
  sender.Subscribe<dtpdu::construct_t>([](const dtpdu::construct_t&) {});
  now_ms_ += 5;
  auto seq = sender.Publish(sample::Construct());
  ASSERT_TRUE(seq.ok()) << seq.error().message;
  ASSERT_TRUE(bus_.HandleTimeout(0).ok());
  EXPECT_EQ(handled_, 1);
  EXPECT_EQ(bus_.accepted(), 1u);
  EXPECT_EQ(bus_.rejects().total(), 0u);
  EXPECT_EQ(sender.own_echoes(), 1u);  // echo handling is unchanged
  EXPECT_EQ(sender.rejects().total(), 0u);

  // On the wire: the LCM PDU, then the trailer naming the sender, its incarnation (its start)
  // and sequence 1, sent now.
  ASSERT_EQ(wire.size(), 1u);
  const size_t lcm_bytes = EncodePdu(sample::Construct()).size();
  ASSERT_EQ(wire[0].size(), lcm_bytes + kAuthTrailerBytes);
  const auto t = ParseTrailer(wire[0]);
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->sender, (NodeAddress{1, 2}));
  EXPECT_EQ(t->incarnation, static_cast<uint64_t>(kStartMs));
  EXPECT_EQ(t->sequence, 1u);
  EXPECT_EQ(t->send_time_ms, static_cast<uint64_t>(kStartMs + 5));
  ASSERT_NE(sender.authenticator(), nullptr);
  EXPECT_EQ(sender.authenticator()->incarnation(), static_cast<uint64_t>(kStartMs));

  // LCM's own decoder reads the PDU and stops before the trailer.
  dtpdu::construct_t decoded;
  EXPECT_EQ(decoded.decode(wire[0].data(), 0, static_cast<int>(wire[0].size())),
            static_cast<int>(lcm_bytes));
  EXPECT_EQ(decoded.sender_seq, seq.value());
}

TEST_F(AuthTest, DropsAPduWithoutATrailer) {
  Inject(EncodePdu(sample::Construct()));
  EXPECT_EQ(count(RejectReason::kUnauthenticated), 1u);
  EXPECT_EQ(handled_, 0);
}

// A PDU as the former trailer version signed it ("DTA1", HMAC-SHA512-256 under the raw key) is
// refused as unauthenticated, not read as a trailer of this version.
TEST_F(AuthTest, DropsTheFormerTrailerVersionAsUnauthenticated) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  std::vector<uint8_t> bytes = Signed(member);
  const size_t signed_end = bytes.size() - kMacBytes;
  bytes[bytes.size() - kAuthTrailerBytes + 3] = '1';
  ASSERT_GE(sodium_init(), 0);
  const std::vector<uint8_t> raw_key(32, 0x11);  // key_'s bytes
  crypto_auth(bytes.data() + signed_end, bytes.data(), signed_end, raw_key.data());
  Inject(bytes);
  EXPECT_EQ(count(RejectReason::kUnauthenticated), 1u);
  EXPECT_EQ(count(RejectReason::kBadMac), 0u);
  EXPECT_EQ(handled_, 0);
  std::span<const uint8_t> pdu;
  PduAuthenticator receiver({2, 2}, Auth(key_, &now_ms_));
  const auto r = receiver.Verify(bytes, pdu);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->reason, RejectReason::kUnauthenticated);
  EXPECT_NE(r->detail.find("trailer of version '1'"), std::string::npos) << r->detail;
  // The same bytes with this version's magic (and still the former MAC): a bad MAC.
  bytes[bytes.size() - kAuthTrailerBytes + 3] = '2';
  Inject(bytes);
  EXPECT_EQ(count(RejectReason::kBadMac), 1u);
  EXPECT_EQ(handled_, 0);
}

TEST_F(AuthTest, DropsAPduSignedWithAnotherKey) {
  PduAuthenticator stranger({1, 2}, Auth(Key(0x22), &now_ms_));
  Inject(Signed(stranger));
  EXPECT_EQ(count(RejectReason::kBadMac), 1u);
  EXPECT_EQ(handled_, 0);
}

TEST_F(AuthTest, DropsAPduChangedAfterSigning) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  std::vector<uint8_t> bytes = Signed(member);
  bytes[40] ^= 0x01;  // inside the PDU: a feature field
  Inject(bytes);
  bytes = Signed(member);
  bytes[bytes.size() - kAuthTrailerBytes + 23] ^= 0x01;  // the trailer's sequence
  Inject(bytes);
  EXPECT_EQ(count(RejectReason::kBadMac), 2u);
  EXPECT_EQ(handled_, 0);
}

TEST_F(AuthTest, DropsAPduWhoseTrailerNamesAnotherSender) {
  // A key holder (5:5) signing a PDU that claims to come from 1:2.
  PduAuthenticator other({5, 5}, Auth(key_, &now_ms_));
  Inject(Signed(other));
  EXPECT_EQ(count(RejectReason::kSenderMismatch), 1u);
  EXPECT_EQ(handled_, 0);
}

TEST_F(AuthTest, DropsAReplayOfTheSameBytes) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  const std::vector<uint8_t> bytes = Signed(member);
  Inject(bytes);
  Inject(bytes);
  EXPECT_EQ(handled_, 1);
  EXPECT_EQ(count(RejectReason::kReplayed), 1u);
  Inject(Signed(member));  // the next sequence is new
  EXPECT_EQ(handled_, 2);
}

TEST_F(AuthTest, DropsAnOlderIncarnationOfASender) {
  PduAuthenticator before_restart({1, 2}, Auth(key_, &now_ms_, 1000));
  PduAuthenticator after_restart({1, 2}, Auth(key_, &now_ms_, 2000));
  const std::vector<uint8_t> old_bytes = Signed(before_restart);
  Signed(before_restart);  // sequence 2, never delivered
  const std::vector<uint8_t> unseen_old = Signed(before_restart);
  Inject(old_bytes);
  Inject(Signed(after_restart));
  Inject(unseen_old);  // never seen, but from the life before the restart
  EXPECT_EQ(handled_, 2);
  EXPECT_EQ(count(RejectReason::kReplayed), 1u);
}

TEST_F(AuthTest, DropsSequencesBehindTheWindow) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  const std::vector<uint8_t> first = Signed(member);
  std::vector<uint8_t> last;
  for (uint64_t i = 0; i < ReplayWindow::kSize; ++i) last = Signed(member);
  Inject(last);   // sequence kSize + 1
  Inject(first);  // sequence 1: kSize behind, no longer tracked
  EXPECT_EQ(handled_, 1);
  EXPECT_EQ(count(RejectReason::kReplayed), 1u);
}

TEST_F(AuthTest, DropsPdusSentOutsideTheClockTolerance) {
  int64_t sender_now = now_ms_ - kDefaultClockTolerance.count() - 1;
  PduAuthenticator member({1, 2}, Auth(key_, &sender_now));
  Inject(Signed(member));  // 30.001 s old
  sender_now = now_ms_ + kDefaultClockTolerance.count() + 1;
  Inject(Signed(member));  // 30.001 s in the future
  EXPECT_EQ(count(RejectReason::kStale), 2u);
  EXPECT_EQ(handled_, 0);
  sender_now = now_ms_ - kDefaultClockTolerance.count();
  Inject(Signed(member));  // exactly at the tolerance
  sender_now = now_ms_ + kDefaultClockTolerance.count();
  Inject(Signed(member));
  EXPECT_EQ(handled_, 2);
  EXPECT_EQ(count(RejectReason::kStale), 2u);
}

TEST_F(AuthTest, TheToleranceIsConfigurable) {
  LcmTransport t("memq://", sample::kSampleExercise);
  PduAuthConfig strict = Auth(key_, &now_ms_);
  strict.clock_tolerance = std::chrono::milliseconds(2000);
  PduBus receiver(t, Config({2, 2}, strict));
  int got = 0;
  receiver.Subscribe<dtpdu::construct_t>([&](const dtpdu::construct_t&) { ++got; });
  int64_t sender_now = now_ms_ - 2001;
  PduAuthenticator member({1, 2}, Auth(key_, &sender_now));
  ASSERT_TRUE(t.Publish(PduType::kConstruct, Signed(member)).ok());
  sender_now = now_ms_ - 1999;
  ASSERT_TRUE(t.Publish(PduType::kConstruct, Signed(member)).ok());
  ASSERT_TRUE(receiver.HandleTimeout(0).ok());
  EXPECT_EQ(got, 1);
  EXPECT_EQ(receiver.rejects().count(RejectReason::kStale), 1u);
}

TEST_F(AuthTest, ForgetsASenderSilentForTwiceTheTolerance) {
  // A process restarted after its clock went back: its new incarnation is older. It is refused
  // until the receiver has heard nothing accepted from the old one for 2 x tolerance.
  PduAuthenticator old_life({1, 2}, Auth(key_, &now_ms_, 5000));
  PduAuthenticator new_life({1, 2}, Auth(key_, &now_ms_, 4000));
  Inject(Signed(old_life));
  now_ms_ += 2 * kDefaultClockTolerance.count();
  Inject(Signed(new_life));
  EXPECT_EQ(count(RejectReason::kReplayed), 1u);
  now_ms_ += 1;
  Inject(Signed(new_life));
  EXPECT_EQ(handled_, 2);
  EXPECT_EQ(count(RejectReason::kReplayed), 1u);
}

TEST_F(AuthTest, ItsOwnEchoesAreDroppedBeforeAuthentication) {
  // They can reach no handler, so no MAC is spent on them; a forgery naming this node (2:2) as
  // its sender is dropped the same way.
  dtpdu::construct_t pdu = sample::Construct();
  pdu.sender = ToPdu(NodeAddress{2, 2});
  Inject(EncodePdu(pdu));
  EXPECT_EQ(bus_.own_echoes(), 1u);
  EXPECT_EQ(bus_.rejects().total(), 0u);
  EXPECT_EQ(handled_, 0);
  EXPECT_EQ(bus_.authenticator()->senders_tracked(), 0u);
}

TEST_F(AuthTest, ValidationStillRunsOnAuthenticPdus) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  dtpdu::construct_t pdu = sample::Construct();
  pdu.width_m = std::nan("");
  Inject(Signed(member, pdu));
  EXPECT_EQ(count(RejectReason::kNotFinite), 1u);
  EXPECT_EQ(handled_, 0);
}

TEST_F(AuthTest, DropsOversizedBytesBeforeLookingForATrailer) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  std::vector<uint8_t> bytes = EncodePdu(sample::Construct());
  bytes.resize(kMaxPduBytes + 1 - kAuthTrailerBytes);
  member.Sign(bytes);
  ASSERT_FALSE(transport_.Publish(PduType::kConstruct, bytes).ok());  // LCM refuses to send it
  std::span<const uint8_t> out;
  const auto r = PduAuthenticator({2, 2}, Auth(key_, &now_ms_)).Verify(bytes, out);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->reason, RejectReason::kOversized);
}

TEST_F(AuthTest, NoCorruptionOrTruncationIsAccepted) {
  PduAuthenticator member({1, 2}, Auth(key_, &now_ms_));
  PduAuthenticator receiver({2, 2}, Auth(key_, &now_ms_));
  std::mt19937_64 rng(16);
  std::set<RejectReason> reasons;
  int accepted = 0;
  for (int i = 0; i < 4000; ++i) {
    std::vector<uint8_t> bytes = Signed(member);
    const size_t at = rng() % bytes.size();
    bytes[at] = static_cast<uint8_t>(bytes[at] ^ (1 + rng() % 255));
    std::span<const uint8_t> out;
    if (auto r = receiver.Verify(bytes, out)) {
      reasons.insert(r->reason);
    } else {
      ++accepted;
    }
  }
  const std::vector<uint8_t> whole = Signed(member);
  for (size_t n = 0; n < whole.size(); ++n) {
    std::span<const uint8_t> out;
    if (auto r = receiver.Verify(std::span<const uint8_t>(whole).first(n), out)) {
      reasons.insert(r->reason);
    } else {
      ++accepted;
    }
  }
  EXPECT_EQ(accepted, 0);
  EXPECT_EQ(reasons,
            (std::set<RejectReason>{RejectReason::kUnauthenticated, RejectReason::kBadMac}));
  std::span<const uint8_t> out;
  EXPECT_EQ(receiver.Verify(whole, out), std::nullopt);  // the intact one is accepted
  EXPECT_EQ(out.size(), whole.size() - kAuthTrailerBytes);
}

TEST(PduAuth, AKeylessBusRefusesTrailersAsTrailingBytes) {
  // Mixing keyed and keyless processes in one exercise never half-works: each refuses the other.
  int64_t now = kStartMs;
  LcmTransport t("memq://", sample::kSampleExercise);
  PduBusConfig keyless = Config({2, 2}, PduAuthConfig{});
  PduBus plain(t, keyless);
  PduBus keyed(t, Config({1, 2}, Auth(Key(0x11), &now)));
  plain.Subscribe<dtpdu::construct_t>([](const dtpdu::construct_t&) {});
  keyed.Subscribe<dtpdu::destruct_t>([](const dtpdu::destruct_t&) {});
  ASSERT_TRUE(keyed.Publish(sample::Construct()).ok());
  ASSERT_TRUE(plain.Publish(sample::Destruct()).ok());
  ASSERT_TRUE(t.HandleTimeout(0).ok());
  EXPECT_EQ(plain.authenticator(), nullptr);
  EXPECT_EQ(plain.rejects().count(RejectReason::kTrailingBytes), 1u);
  EXPECT_EQ(keyed.rejects().count(RejectReason::kUnauthenticated), 1u);
}

TEST(PduAuth, RefusesABadConfig) {
  int64_t now = kStartMs;
  PduAuthConfig no_key = Auth(nullptr, &now);
  EXPECT_THROW(PduAuthenticator({1, 1}, no_key), std::invalid_argument);
  PduAuthConfig zero = Auth(Key(1), &now);
  zero.clock_tolerance = std::chrono::milliseconds(0);
  EXPECT_THROW(PduAuthenticator({1, 1}, zero), std::invalid_argument);
  LcmTransport t("memq://", sample::kSampleExercise);
  EXPECT_THROW(PduBus(t, Config({1, 1}, zero)), std::invalid_argument);
}

}  // namespace
}  // namespace dt
