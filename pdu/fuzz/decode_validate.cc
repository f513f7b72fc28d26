#include "pdu/fuzz/decode_validate.h"

#include <cstdlib>
#include <span>

#include "pdu/batch.h"
#include "pdu/conversion.h"
#include "pdu/pdu_auth.h"
#include "pdu/validation.h"
#include "pdu/vehicle_state.h"

namespace dt::fuzz {
namespace {

constexpr ValidationContext kContext{7, 1000.0, 1000.0};

template <typename Pdu>
bool One(std::span<const uint8_t> bytes) {
  Pdu pdu;
  if (DecodeAndValidate(bytes, kContext, pdu)) return false;
  if (EncodePdu(pdu) != std::vector<uint8_t>(bytes.begin(), bytes.end())) std::abort();
  if constexpr (PduTraits<Pdu>::kType == PduType::kConstruct) {
    auto f = FromConstruct(pdu);
    if (!f || !ValidateFeatureParams(f.value().params)) std::abort();
  } else if constexpr (PduTraits<Pdu>::kType == PduType::kUpdate) {
    auto f = FromUpdate(pdu);
    if (!f || !ValidateFeatureParams(f.value().params)) std::abort();
  } else if constexpr (PduTraits<Pdu>::kType == PduType::kEarthMove) {
    // What passes is a valid earth move, and its PDU again is one of the same posts.
    auto f = FromEarthMove(pdu);
    if (!f || !ValidateFeatureParams(f.value().params)) std::abort();
    if (FromEarthMove(ToEarthMove(f.value())).value() != f.value()) std::abort();
  } else if constexpr (PduTraits<Pdu>::kType == PduType::kVehicleState) {
    // What a handler sees converts to fields and back to the very same PDU.
    auto again = ToVehicleState(FromVehicleState(pdu));
    again.header = pdu.header;
    again.sender = pdu.sender;
    again.sender_seq = pdu.sender_seq;
    if (EncodePdu(again) != EncodePdu(pdu)) std::abort();
  }
  return true;
}

// A batch is taken whole or not at all: what is accepted re-encodes to the same bytes, and each
// member (rebuilt, if a delta), sent alone, would be accepted too.
bool OneBatch(std::span<const uint8_t> bytes) {
  std::vector<MemberPdu> members;
  if (DecodeBatch(bytes, kContext, members)) return false;
  dtpdu::batch_t batch;
  if (DecodePdu(bytes, batch)) std::abort();
  if (EncodePdu(batch) != std::vector<uint8_t>(bytes.begin(), bytes.end())) std::abort();
  if (members.size() != batch.members.size() || members.empty()) std::abort();
  std::vector<uint8_t> previous, member(kMaxPduBytes);
  for (size_t i = 0; i < members.size(); ++i) {
    const auto& m = batch.members[i];
    std::vector<uint8_t> whole = m.bytes;
    if (static_cast<MemberEncoding>(m.encoding) == MemberEncoding::kDelta) {
      size_t length = 0;
      if (ApplyMemberDelta(previous, m.bytes, member, &length)) std::abort();
      whole.assign(member.begin(), member.begin() + static_cast<std::ptrdiff_t>(length));
    }
    const bool alone = std::visit(
        [&](const auto& pdu) {
          const std::vector<uint8_t> encoded = EncodePdu(pdu);
          return encoded == whole && One<std::decay_t<decltype(pdu)>>(encoded);
        },
        members[i]);
    if (!alone) std::abort();
    previous = std::move(whole);
  }
  return true;
}

bool DecodeAs(uint8_t selector, std::span<const uint8_t> bytes) {
  if (selector >= kFuzzBatch) return OneBatch(bytes);
  switch (selector % kFuzzTypes) {
    case 0:
      return One<dtpdu::construct_t>(bytes);
    case 1:
      return One<dtpdu::update_t>(bytes);
    case 2:
      return One<dtpdu::destruct_t>(bytes);
    case 3:
      return One<dtpdu::max_feature_t>(bytes);
    case 4:
      return One<dtpdu::playback_t>(bytes);
    case 5:
      return One<dtpdu::anti_entropy_t>(bytes);
    case 6:
      return One<dtpdu::vehicle_state_t>(bytes);
    default:
      return One<dtpdu::earth_move_t>(bytes);
  }
}

}  // namespace

std::vector<uint8_t> FuzzKey() { return std::vector<uint8_t>(32, 0x42); }

bool DecodeValidateOne(const uint8_t* data, size_t size) {
  if (size == 0) return false;
  const std::span<const uint8_t> bytes(data + 1, size - 1);
  if ((data[0] / kFuzzTypes) % 2 == 0) return DecodeAs(data[0], bytes);
  static const auto key = std::make_shared<const ExerciseKey>(FuzzKey());
  // A fresh receiver per input, so its replay window never makes one input depend on another.
  PduAuthenticator receiver(
      {9, 9}, PduAuthConfig{.key = key, .wall_clock_ms = [] { return kFuzzClockMs; }});
  std::span<const uint8_t> pdu;
  if (receiver.Verify(bytes, pdu)) return false;
  // What Verify lets through lies inside the input and ends before the trailer.
  if (pdu.data() != bytes.data() || pdu.size() >= bytes.size()) std::abort();
  return DecodeAs(data[0], pdu);
}

}  // namespace dt::fuzz
