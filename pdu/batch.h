// Batch: several PDUs of one sender in one datagram (batch_t): its size, encoding and decoding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "pdu/member_delta.h"
#include "pdu/validation.h"

namespace dt {

// A member PDU as a handler sees it: one of the eight PDU types that are not a batch.
using MemberPdu = std::variant<dtpdu::construct_t, dtpdu::update_t, dtpdu::destruct_t,
                               dtpdu::max_feature_t, dtpdu::playback_t, dtpdu::anti_entropy_t,
                               dtpdu::vehicle_state_t, dtpdu::earth_move_t>;

// Bytes of a batch_t with no members: fingerprint (8), header (7), sender (4), num_members (2).
inline constexpr size_t kBatchBaseBytes = 8 + 7 + 4 + 2;
// Bytes each member adds besides its own bytes: pdu_type (1), encoding (1), num_bytes (2).
inline constexpr size_t kBatchMemberBytes = 1 + 1 + 2;

// One member to send: its type and its bytes: its LCM encoding (fingerprint included, no
// trailer), or a delta against the member before it (pdu/member_delta.h).
struct BatchMember {
  PduType type;
  std::span<const uint8_t> bytes;
  MemberEncoding encoding = MemberEncoding::kWhole;
};

// Encodes a batch of `members` (header stamped with the protocol version, exercise, kBatch and
// timestamp_dis) into `out`, replacing its contents. The caller keeps it within kMaxPduBytes.
void EncodeBatchInto(uint8_t exercise_id, uint32_t timestamp_dis, NodeAddress sender,
                     std::span<const BatchMember> members, std::vector<uint8_t>& out);

// Decodes a received batch (the bytes after authentication), rebuilds every member given as a
// delta, validates the batch and every member as if each had come alone, and checks that each
// member names the batch's sender. nullopt: `out` holds the members in order. Otherwise the whole
// batch is refused (a bad member's rejection names its place in the batch) and `out` is to be
// ignored: nothing of a refused batch may be used. Never throws.
std::optional<Rejection> DecodeBatch(std::span<const uint8_t> bytes, const ValidationContext& ctx,
                                     std::vector<MemberPdu>& out);

}  // namespace dt
