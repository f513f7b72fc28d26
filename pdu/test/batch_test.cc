#include "pdu/batch.h"

#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "pdu/conversion.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

// Member `bytes` decoded alone as a `Pdu`, validated and checked against the batch's sender.
template <typename Pdu>
std::optional<Rejection> Alone(std::span<const uint8_t> bytes, NodeAddress sender) {
  Pdu pdu;
  if (auto r = DecodeAndValidate(bytes, sample::Context(), pdu)) return r;
  if (FromPdu(pdu.sender) != sender) return Rejection{RejectReason::kSenderMismatch, ""};
  return std::nullopt;
}

std::optional<Rejection> AloneAs(PduType type, std::span<const uint8_t> bytes, NodeAddress sender) {
  switch (type) {
    case PduType::kConstruct:
      return Alone<dtpdu::construct_t>(bytes, sender);
    case PduType::kUpdate:
      return Alone<dtpdu::update_t>(bytes, sender);
    case PduType::kDestruct:
      return Alone<dtpdu::destruct_t>(bytes, sender);
    case PduType::kMaxFeature:
      return Alone<dtpdu::max_feature_t>(bytes, sender);
    case PduType::kPlayback:
      return Alone<dtpdu::playback_t>(bytes, sender);
    case PduType::kAntiEntropy:
      return Alone<dtpdu::anti_entropy_t>(bytes, sender);
    case PduType::kVehicleState:
      return Alone<dtpdu::vehicle_state_t>(bytes, sender);
    case PduType::kEarthMove:
      return Alone<dtpdu::earth_move_t>(bytes, sender);
    case PduType::kBatch:
      break;
  }
  return Rejection{RejectReason::kUnknownPduType, ""};
}

// DecodeBatch as it stood when it decoded a batch_t: the batch decoded and validated whole
// (DecodeAndValidate), then each member alone. A member's rejection keeps only its reason and
// its place, marked "@member i of n"; the rest of the detail is the member's own decoder's.
std::optional<Rejection> Reference(std::span<const uint8_t> bytes, size_t& members) {
  dtpdu::batch_t batch;
  if (auto r = DecodeAndValidate(bytes, sample::Context(), batch)) return r;
  members = batch.members.size();
  std::vector<uint8_t> previous, rebuilt(kMaxPduBytes);
  for (size_t i = 0; i < batch.members.size(); ++i) {
    const auto& m = batch.members[i];
    std::vector<uint8_t> whole = m.bytes;
    std::optional<Rejection> r;
    if (static_cast<MemberEncoding>(m.encoding) == MemberEncoding::kDelta) {
      size_t length = 0;
      r = ApplyMemberDelta(previous, m.bytes, rebuilt, &length);
      whole.assign(rebuilt.begin(), rebuilt.begin() + static_cast<std::ptrdiff_t>(r ? 0 : length));
    }
    if (!r) r = AloneAs(*PduTypeFromRaw(m.pdu_type), whole, FromPdu(batch.sender));
    if (r) {
      r->detail = fmt::format("@member {} of {}", i + 1, batch.members.size());
      return r;
    }
    previous = std::move(whole);
  }
  return std::nullopt;
}

// Five members, the second to the fourth as deltas against the one before.
std::vector<uint8_t> SampleBatch() {
  auto next = sample::Construct();
  next.sender_seq += 1;
  next.feature_number += 1;
  next.position_m[2] += 10.0;
  const std::vector<std::pair<PduType, std::vector<uint8_t>>> pdus = {
      {PduType::kConstruct, EncodePdu(sample::Construct())},
      {PduType::kConstruct, EncodePdu(next)},
      {PduType::kDestruct, EncodePdu(sample::Destruct())},
      {PduType::kAntiEntropy, EncodePdu(sample::AntiEntropySummary())},
      {PduType::kConstruct, EncodePdu(sample::DitchConstruct())}};
  std::vector<std::vector<uint8_t>> deltas(pdus.size());
  std::vector<BatchMember> members;
  for (size_t i = 0; i < pdus.size(); ++i) {
    if (i == 0 || i == 4) {
      members.push_back({pdus[i].first, pdus[i].second});
      continue;
    }
    EncodeMemberDelta(pdus[i - 1].second, pdus[i].second, deltas[i]);
    members.push_back({pdus[i].first, deltas[i], MemberEncoding::kDelta});
  }
  std::vector<uint8_t> out;
  EncodeBatchInto(sample::kSampleExercise, 1, {1, 2}, members, out);
  return out;
}

// The batch is read in place, without a batch_t: on the sample batch and on 20 000 mutations of it
// (bytes flipped, counts and lengths rewritten, cut short, lengthened), it refuses with the
// reason and message of the batch_t decoder, or accepts the same members, into one reused vector.
TEST(DecodeBatch, AgreesWithDecodingABatchTOnMutatedBatches) {
  const std::vector<uint8_t> good = SampleBatch();
  std::vector<MemberPdu> out;  // reused across every case, as PduBus does
  ASSERT_FALSE(DecodeBatch(good, sample::Context(), out));
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(std::get<dtpdu::construct_t>(out[1]).feature_number,
            sample::Construct().feature_number + 1);
  EXPECT_TRUE(std::holds_alternative<dtpdu::anti_entropy_t>(out[3]));
  EXPECT_EQ(EncodePdu(std::get<dtpdu::construct_t>(out[4])), EncodePdu(sample::DitchConstruct()));

  constexpr size_t kCount = 8 + 7 + 4;  // where num_members lies: after fingerprint, header, sender
  std::mt19937_64 rng(20261205);
  int accepted = 0, refused_whole = 0, refused_member = 0;
  for (int round = 0; round < 20000; ++round) {
    std::vector<uint8_t> bytes = good;
    switch (round % 5) {
      case 0:  // a few bytes anywhere
        for (int k = 0; k < 1 + round % 3; ++k) bytes[rng() % bytes.size()] = rng() & 0xff;
        break;
      case 1: {  // num_members: negative, 0, fewer, more
        const int16_t count = static_cast<int16_t>(static_cast<int>(rng() % 12) - 3);
        bytes[kCount] = static_cast<uint8_t>(count >> 8);
        bytes[kCount + 1] = static_cast<uint8_t>(count);
        break;
      }
      case 2: {  // the first member's length: negative, 0, short, long
        const int16_t length = static_cast<int16_t>(static_cast<int>(rng() % 400) - 100);
        bytes[kCount + 4] = static_cast<uint8_t>(length >> 8);
        bytes[kCount + 5] = static_cast<uint8_t>(length);
        break;
      }
      case 3:  // cut short
        bytes.resize(rng() % bytes.size());
        break;
      case 4:  // lengthened, or the first member's type or encoding rewritten
        if (rng() % 3 == 0) {
          bytes.resize(bytes.size() + 1 + rng() % 4, 0);
        } else {
          bytes[kCount + 2 + rng() % 2] = static_cast<uint8_t>(rng() % 3 == 0 ? rng() : rng() % 3);
        }
        break;
    }
    size_t members = 0;
    const auto expected = Reference(bytes, members);
    const auto got = DecodeBatch(bytes, sample::Context(), out);
    ASSERT_EQ(got.has_value(), expected.has_value()) << round << (got ? got->detail : "");
    if (!got) {
      ASSERT_EQ(out.size(), members) << round;
      ++accepted;
      continue;
    }
    ASSERT_EQ(got->reason, expected->reason) << round << ": " << got->detail;
    if (expected->detail.starts_with("@")) {
      ASSERT_TRUE(got->detail.starts_with(expected->detail.substr(1) + " ("))
          << round << ": " << got->detail;
      ++refused_member;
    } else {
      ASSERT_EQ(got->detail, expected->detail) << round;
      ++refused_whole;
    }
  }
  // Every kind of outcome happened, so each was compared.
  EXPECT_GT(accepted, 100);
  EXPECT_GT(refused_whole, 1000);
  EXPECT_GT(refused_member, 100);
}

}  // namespace
}  // namespace dt
