// Datagrams bundling several PDUs (IEEE 1278.2): every PDU taken and counted on its own, a bad
// one dropped without its neighbours, a tail that cannot be framed refused once.
#include <gtest/gtest.h>

#include <vector>

#include "dis/dis_codec.h"
#include "dis/test/golden_pdus.h"

namespace dt::dis {
namespace {

std::vector<uint8_t> Es() { return Encode(testing::GoldenEntityState()); }
std::vector<uint8_t> Point() { return Encode(testing::GoldenPointObjectState()); }
std::vector<uint8_t> Linear() { return Encode(testing::GoldenLinearObjectState()); }

std::vector<uint8_t> Cat(std::initializer_list<std::vector<uint8_t>> pdus) {
  std::vector<uint8_t> out;
  for (const auto& p : pdus) out.insert(out.end(), p.begin(), p.end());
  return out;
}

struct Walk {
  std::vector<Pdu> pdus;
  std::vector<DecodeFailure> failures;
};

Walk WalkBundle(Decoder& d, const std::vector<uint8_t>& datagram) {
  Walk w;
  d.DecodeBundle(datagram, [&](const DecodeResult& r) {
    if (r.ok()) {
      w.pdus.push_back(r.pdu());
    } else {
      EXPECT_FALSE(r.error().message.empty());
      w.failures.push_back(r.error().failure);
    }
  });
  return w;
}

TEST(DisBundle, EveryPduOfABundleIsTakenInOrder) {
  Decoder d(5);
  const Walk w = WalkBundle(d, Cat({Es(), Point(), Linear(), Es()}));
  ASSERT_EQ(w.pdus.size(), 4u);
  EXPECT_TRUE(w.failures.empty());
  // Each equal to the same PDU decoded alone (the encoder fills in type and length).
  EXPECT_EQ(w.pdus[0], DecodePdu(Es()).pdu());
  EXPECT_EQ(w.pdus[1], DecodePdu(Point()).pdu());
  EXPECT_EQ(w.pdus[2], DecodePdu(Linear()).pdu());
  EXPECT_EQ(w.pdus[3], DecodePdu(Es()).pdu());
  EXPECT_EQ(d.counters().entity_state, 2u);
  EXPECT_EQ(d.counters().point_object_state, 1u);
  EXPECT_EQ(d.counters().linear_object_state, 1u);
  EXPECT_EQ(d.counters().rejected_total(), 0u);
}

TEST(DisBundle, ASinglePduIsABundleOfOne) {
  Decoder d(5);
  const Walk w = WalkBundle(d, Es());
  EXPECT_EQ(w.pdus.size(), 1u);
  EXPECT_TRUE(w.failures.empty());
}

TEST(DisBundle, ABadPduIsDroppedAndItsNeighboursKept) {
  std::vector<uint8_t> unknown_type = Es();
  unknown_type[2] = 2;  // Fire
  std::vector<uint8_t> foreign = Point();
  foreign[1] = 6;
  std::vector<uint8_t> nan = Es();
  for (int i = 0; i < 8; ++i) nan[48 + i] = i < 2 ? 0xFF : 0;  // x is NaN
  Decoder d(5);
  const Walk w = WalkBundle(d, Cat({Es(), unknown_type, Linear(), foreign, nan, Point()}));
  EXPECT_EQ(w.pdus.size(), 3u);
  EXPECT_EQ(w.failures, (std::vector<DecodeFailure>{DecodeFailure::kUnsupportedPduType,
                                                    DecodeFailure::kForeignExercise,
                                                    DecodeFailure::kNonFinite}));
  EXPECT_EQ(d.counters().rejected_total(), 3u);
  EXPECT_EQ(d.counters().entity_state + d.counters().point_object_state +
                d.counters().linear_object_state,
            3u);
}

TEST(DisBundle, EveryTruncationKeepsTheWholePdusBeforeTheCut) {
  const std::vector<uint8_t> whole = Cat({Es(), Point(), Linear()});
  const size_t ends[] = {Es().size(), Es().size() + Point().size(), whole.size()};
  for (size_t n = 1; n <= whole.size(); ++n) {
    const std::vector<uint8_t> cut(whole.begin(), whole.begin() + static_cast<long>(n));
    Decoder d(5);
    const Walk w = WalkBundle(d, cut);
    size_t complete = 0;
    for (size_t e : ends) complete += e <= n ? 1 : 0;
    ASSERT_EQ(w.pdus.size(), complete) << n << " bytes";
    const bool clean = n == ends[0] || n == ends[1] || n == ends[2];
    ASSERT_EQ(w.failures.size(), clean ? 0u : 1u) << n << " bytes";
    if (!clean) {
      // A tail under a header is too short; past one, its length field runs past the end.
      const size_t start = complete == 0 ? 0 : ends[complete - 1];
      EXPECT_EQ(w.failures[0],
                n - start < kHeaderSize ? DecodeFailure::kTooShort : DecodeFailure::kLengthMismatch)
          << n << " bytes";
    }
    EXPECT_EQ(d.counters().rejected_total(), w.failures.size());
  }
}

TEST(DisBundle, ALengthFieldThatFramesNothingEndsTheWalk) {
  std::vector<uint8_t> zero = Point();
  zero[8] = zero[9] = 0;  // a length of 0 would never move on
  Decoder d(5);
  const Walk w = WalkBundle(d, Cat({Es(), zero, Es()}));
  EXPECT_EQ(w.pdus.size(), 1u);
  EXPECT_EQ(w.failures, std::vector<DecodeFailure>{DecodeFailure::kLengthMismatch});
}

TEST(DisBundle, EmptyAndOversizedDatagramsAreOneRefusalEach) {
  Decoder d(5);
  EXPECT_EQ(WalkBundle(d, {}).failures, std::vector<DecodeFailure>{DecodeFailure::kTooShort});
  const std::vector<uint8_t> huge(kMaxPduSize + 1, 0);
  EXPECT_EQ(WalkBundle(d, huge).failures, std::vector<DecodeFailure>{DecodeFailure::kTooLong});
  EXPECT_EQ(d.counters().rejected_total(), 2u);
}

TEST(DisBundle, FrameAtNamesWhereTheTailBroke) {
  std::vector<uint8_t> b = Cat({Es(), Es()});
  b.resize(b.size() - 4);
  const PduFrame f = FrameAt(b, Es().size());
  ASSERT_TRUE(f.error.has_value());
  EXPECT_EQ(f.error->failure, DecodeFailure::kLengthMismatch);
  EXPECT_NE(f.error->message.find("at byte 144"), std::string::npos) << f.error->message;
  EXPECT_NE(f.error->message.find("140 bytes left"), std::string::npos) << f.error->message;
}

}  // namespace
}  // namespace dt::dis
