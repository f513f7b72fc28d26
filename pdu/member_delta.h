// Batch member deltas: a member written as the bytes where it differs from the member before it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "pdu/validation.h"

namespace dt {

// How a batch member's bytes hold it (batch_member_t.encoding; docs/pdu.md "Member deltas").
enum class MemberEncoding : uint8_t {
  kWhole = 0,  // its LCM encoding, exactly as it would travel alone
  kDelta = 1,  // its length, then runs of bytes that differ from the member before it
};

// Bytes a delta takes before its runs: the member's length, an int16 as LCM writes it.
inline constexpr size_t kMemberDeltaLengthBytes = 2;
// Bytes each run takes besides its literal bytes: skip (1) and count (1).
inline constexpr size_t kMemberDeltaRunBytes = 2;

// Writes `member` as a delta against `previous` into `out`, replacing its contents: the length,
// then runs of (skip, count, count literal bytes), each run's skip counted from where the one
// before ended. Bytes of `member` past the end of `previous` differ from 0. Equal stretches of
// at most two bytes between differing ones are written as literals (a new run would cost two).
// The result may be longer than `member` when the two have little in common: the caller picks.
// `member` must be 1..kMaxPduBytes bytes.
void EncodeMemberDelta(std::span<const uint8_t> previous, std::span<const uint8_t> member,
                       std::vector<uint8_t>& out);

// Rebuilds a member from `previous` and its `delta` into `out` (at least kMaxPduBytes long):
// `previous`'s first `length` bytes (zeros past its end), the runs written over them. nullopt:
// out's first `*length` bytes are the member. Otherwise the delta is refused (a length outside
// 1..kMaxPduBytes, a run cut short or ending past the member's length) and `out` is to be
// ignored. `previous` must not overlap `out`. Never throws.
std::optional<Rejection> ApplyMemberDelta(std::span<const uint8_t> previous,
                                          std::span<const uint8_t> delta, std::span<uint8_t> out,
                                          size_t* length);

}  // namespace dt
