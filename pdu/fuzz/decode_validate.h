// DecodeValidateOne: the body of the decode+validate fuzz target, shared with the replay test.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dt::fuzz {

// The first byte picks the PDU type (modulo kFuzzTypes: Construct, Update, Destruct, MaxFeature,
// Playback, AntiEntropy, VehicleState, EarthMove; a Batch when byte >= kFuzzBatch) and, when
// (byte / kFuzzTypes) is odd, that the
// bytes arrive authenticated: they go through a PduAuthenticator's Verify first (key FuzzKey(),
// clock FuzzClockMs(), receiver 9:9), as on a keyed bus, and only the PDU part it accepts is
// decoded. The rest are the received bytes. Decodes and validates them as a receiver would, and for
// an accepted PDU checks the invariants that must hold for anything a handler may see: it
// re-encodes to the same bytes, and a Construct/Update converts to a feature that
// ValidateFeatureParams accepts; an accepted batch re-encodes to the same bytes and each of its
// members is accepted alone too. A broken invariant aborts. Returns true if accepted.
bool DecodeValidateOne(const uint8_t* data, size_t size);

// PDU types the selector byte chooses among; selector t + kFuzzTypes is type t, authenticated.
inline constexpr uint8_t kFuzzTypes = 8;
// Selectors from this one on decode a Batch (parity of byte / kFuzzTypes still picks signing).
inline constexpr uint8_t kFuzzBatch = 128;

// The authenticated inputs' key (32 bytes of 0x42) and fixed wall clock (ms since the epoch), so
// the corpus can hold signed PDUs that stay fresh.
std::vector<uint8_t> FuzzKey();
inline constexpr int64_t kFuzzClockMs = 1'800'000'000'000;

}  // namespace dt::fuzz
