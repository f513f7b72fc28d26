#include "pdu/member_delta.h"

#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "pdu/pdu_type.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

std::vector<uint8_t> Rebuilt(const std::vector<uint8_t>& previous,
                             const std::vector<uint8_t>& delta) {
  std::vector<uint8_t> out(kMaxPduBytes);
  size_t length = 0;
  const auto r = ApplyMemberDelta(previous, delta, out, &length);
  EXPECT_FALSE(r) << r->detail;
  out.resize(r ? 0 : length);
  return out;
}

// The next Construct of a burst: what PduBus packs behind the one before.
TEST(MemberDelta, TheNextConstructOfABurstTakesAFractionOfItsBytes) {
  const auto first = sample::Construct();
  const auto a = EncodePdu(first), b = EncodePdu(sample::NextInBurst(first));
  std::vector<uint8_t> delta;
  EncodeMemberDelta(a, b, delta);
  EXPECT_LT(delta.size() * 3, b.size()) << delta.size() << " of " << b.size();
  EXPECT_EQ(Rebuilt(a, delta), b);
}

TEST(MemberDelta, AnEqualMemberIsItsLengthAlone) {
  const auto a = EncodePdu(sample::Update());
  std::vector<uint8_t> delta;
  EncodeMemberDelta(a, a, delta);
  ASSERT_EQ(delta.size(), kMemberDeltaLengthBytes);
  EXPECT_EQ(Rebuilt(a, delta), a);
}

// Lengths differing either way, members sharing nothing, equal stretches past 255 bytes and
// differing ones longer than a run: every pair rebuilds exactly.
TEST(MemberDelta, RandomPairsRebuildExactly) {
  std::mt19937_64 rng(20261205);
  std::vector<uint8_t> delta;
  for (int round = 0; round < 5000; ++round) {
    std::vector<uint8_t> a(rng() % (kMaxPduBytes + 1)), b(1 + rng() % kMaxPduBytes);
    for (auto& x : a) x = static_cast<uint8_t>(rng() % 4 == 0 ? rng() : 0);
    const int sharing = static_cast<int>(rng() % 4);  // 0: unrelated ... 3: a few changes
    for (size_t i = 0; i < b.size(); ++i) {
      const bool copy = i < a.size() && static_cast<int>(rng() % 4) < sharing;
      b[i] = copy ? a[i] : static_cast<uint8_t>(rng());
    }
    if (round % 7 == 0 && b.size() > 600) {  // a long equal stretch
      for (size_t i = 10; i < 590 && i < a.size(); ++i) b[i] = a[i];
    }
    EncodeMemberDelta(a, b, delta);
    ASSERT_EQ(Rebuilt(a, delta), b) << round;
  }
}

TEST(MemberDelta, BadDeltasAreRefused) {
  const std::vector<uint8_t> previous(20, 7);
  std::vector<uint8_t> out(kMaxPduBytes);
  size_t length = 0;
  struct Case {
    std::vector<uint8_t> delta;
    RejectReason reason;
    const char* detail;
  };
  const std::vector<Case> cases = {
      {{0}, RejectReason::kTruncated, "delta of 1 bytes has no length"},
      {{0, 0}, RejectReason::kOutOfRange, "delta length 0 outside 1..1400"},
      {{0xff, 0xff}, RejectReason::kOutOfRange, "delta length -1 outside 1..1400"},
      {{0x05, 0x79}, RejectReason::kOutOfRange, "delta length 1401 outside 1..1400"},
      {{0, 20, 3}, RejectReason::kTruncated, "delta run at byte 2 of 3 cut short"},
      {{0, 20, 0, 2, 9}, RejectReason::kTruncated, "delta run of 2 bytes at byte 4 of 5 cut short"},
      {{0, 20, 19, 2, 9, 9},
       RejectReason::kTruncated,
       "delta run to byte 21 past the member's 20 bytes"},
      {{0, 20, 255, 0},
       RejectReason::kTruncated,
       "delta run to byte 255 past the member's 20 bytes"},
  };
  for (const Case& c : cases) {
    const auto r = ApplyMemberDelta(previous, c.delta, out, &length);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->reason, c.reason);
    EXPECT_EQ(r->detail, c.detail);
  }
  // The same runs within the member are fine, and past the previous member's end it is zeros.
  const std::vector<uint8_t> ok = {0, 24, 18, 2, 9, 9};
  ASSERT_FALSE(ApplyMemberDelta(previous, ok, out, &length));
  ASSERT_EQ(length, 24u);
  const std::vector<uint8_t> want = {7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7,
                                     7, 7, 7, 7, 7, 7, 9, 9, 0, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(out.begin(), out.begin() + 24), want);
}

}  // namespace
}  // namespace dt
