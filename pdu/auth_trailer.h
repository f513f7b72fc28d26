// AuthTrailer: the bytes appended after an LCM-encoded PDU that authenticate it (docs/pdu.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "base/feature_id.h"
#include "pdu/exercise_key.h"

namespace dt {

// Layout, all integers big-endian like LCM's, 64 bytes:
//   offset  0  magic "DTA2" (4 bytes; the 2 is the trailer version: "DTA1", whose MAC was
//              HMAC-SHA512-256, is refused like any bytes without a trailer)
//   offset  4  sender site (u16), offset 6 sender host (u16)
//   offset  8  incarnation (u64): the sender process's start, wall-clock ms since the Unix epoch
//   offset 16  sequence (u64): 1, 2, ... per sender incarnation, one per PDU sent
//   offset 24  send time (u64): wall-clock ms since the Unix epoch when the PDU was sent
//   offset 32  MAC (32 bytes): keyed BLAKE2b-256 under the exercise key (exercise_key.h) of
//              <the LCM-encoded PDU> || <trailer bytes 0..31>
// The LCM decoders of every language read the PDU from the front and ignore what follows, so a
// tool without the key still decodes authenticated traffic.
inline constexpr std::array<uint8_t, 4> kAuthMagic = {'D', 'T', 'A', '2'};
inline constexpr size_t kAuthSignedBytes = 32;  // trailer bytes covered by the MAC
inline constexpr size_t kAuthTrailerBytes = kAuthSignedBytes + kMacBytes;
static_assert(kAuthTrailerBytes <= 128, "the DDS carrier keeps at most 128 trailing bytes");

struct AuthTrailer {
  NodeAddress sender;
  uint64_t incarnation = 0;
  uint64_t sequence = 0;
  uint64_t send_time_ms = 0;
  Mac mac{};
};

// Writes the signed part of a trailer (magic, sender, incarnation, sequence, send time).
void EncodeSignedPart(const AuthTrailer& t, std::span<uint8_t, kAuthSignedBytes> out);

// Appends the whole trailer (signed part, then t.mac) to `out`.
void AppendTrailer(const AuthTrailer& t, std::vector<uint8_t>& out);

// The trailer at the end of `bytes`; nullopt if they are too short to hold one after a PDU or
// the magic is missing. The PDU is bytes[0, bytes.size() - kAuthTrailerBytes).
std::optional<AuthTrailer> ParseTrailer(std::span<const uint8_t> bytes);

}  // namespace dt
