// PduTraits and EncodePdu: which PduType each generated LCM type is, and its wire encoding.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "base/demand.h"
#include "base/feature_id.h"
#include "dtpdu/anti_entropy_t.hpp"
#include "dtpdu/batch_t.hpp"
#include "dtpdu/construct_t.hpp"
#include "dtpdu/destruct_t.hpp"
#include "dtpdu/earth_move_t.hpp"
#include "dtpdu/max_feature_t.hpp"
#include "dtpdu/playback_t.hpp"
#include "dtpdu/update_t.hpp"
#include "dtpdu/vehicle_state_t.hpp"
#include "pdu/pdu_type.h"

namespace dt {

template <typename Pdu>
struct PduTraits;
template <>
struct PduTraits<dtpdu::construct_t> {
  static constexpr PduType kType = PduType::kConstruct;
};
template <>
struct PduTraits<dtpdu::update_t> {
  static constexpr PduType kType = PduType::kUpdate;
};
template <>
struct PduTraits<dtpdu::destruct_t> {
  static constexpr PduType kType = PduType::kDestruct;
};
template <>
struct PduTraits<dtpdu::max_feature_t> {
  static constexpr PduType kType = PduType::kMaxFeature;
};
template <>
struct PduTraits<dtpdu::playback_t> {
  static constexpr PduType kType = PduType::kPlayback;
};
template <>
struct PduTraits<dtpdu::anti_entropy_t> {
  static constexpr PduType kType = PduType::kAntiEntropy;
};
template <>
struct PduTraits<dtpdu::earth_move_t> {
  static constexpr PduType kType = PduType::kEarthMove;
};
template <>
struct PduTraits<dtpdu::vehicle_state_t> {
  static constexpr PduType kType = PduType::kVehicleState;
};
// Decoded and validated like the others, but no handler sees a batch: PduBus hands its members
// on (pdu/batch.h).
template <>
struct PduTraits<dtpdu::batch_t> {
  static constexpr PduType kType = PduType::kBatch;
};

template <typename Pdu>
concept AnyPdu = requires {
  PduTraits<Pdu>::kType;
};

// LCM encoding: the 8-byte fingerprint, then the fields big-endian in declaration order.
// Replaces the contents of `out`, reusing its capacity.
template <AnyPdu Pdu>
void EncodePduInto(const Pdu& pdu, std::vector<uint8_t>& out) {
  out.resize(static_cast<size_t>(pdu.getEncodedSize()));
  const int n = pdu.encode(out.data(), 0, static_cast<int>(out.size()));
  DT_DEMAND(n == static_cast<int>(out.size()));  // LCM sized the buffer itself
}

template <AnyPdu Pdu>
std::vector<uint8_t> EncodePdu(const Pdu& pdu) {
  std::vector<uint8_t> bytes;
  EncodePduInto(pdu, bytes);
  return bytes;
}

// Every PDU type starts with the header (7 bytes) and the sender (site, host) right after the
// fingerprint, so a carrier can see who sent a message without decoding it (fault injection's
// partitions). nullopt if the bytes are too short. The value is unvalidated.
std::optional<NodeAddress> PeekSender(std::span<const uint8_t> bytes);

// Byte offset of sender.site in every encoded PDU.
inline constexpr size_t kSenderOffset = 8 + 7;

}  // namespace dt
