// DecodeValidateOne: the body of the decode+validate fuzz target, shared with the replay test.
#pragma once

#include <cstddef>
#include <cstdint>

namespace dt::fuzz {

// The first byte picks the PDU type (modulo 6: Construct, Update, Destruct, MaxFeature,
// Playback, AntiEntropy); the rest are the received bytes. Decodes and validates them as a receiver
// would, and for an accepted PDU checks the invariants that must hold for anything a handler may
// see: it re-encodes to the same bytes, and a Construct/Update converts to a feature that
// ValidateFeatureParams accepts. A broken invariant aborts. Returns true if accepted.
bool DecodeValidateOne(const uint8_t* data, size_t size);

}  // namespace dt::fuzz
