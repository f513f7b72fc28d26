// DecodeOne: the body of the DIS decoder's fuzz target, shared with the replay test.
#pragma once

#include <cstddef>
#include <cstdint>

namespace dt::dis::fuzz {

// Decodes the bytes as one received datagram of exercise kFuzzExercise and, for an accepted
// PDU, checks what must hold for anything the gateway may see: it re-encodes to a datagram of
// the same size that decodes to the same PDU, and the mapping to a vehicle pose or a feature
// either refuses it with a reason or gives finite values (a feature FeatureToDis takes back
// without throwing). The same bytes are also read as a bundle of PDUs (IEEE 1278.2, as the
// gateway reads every datagram): each frame decodes as it would alone, with the same checks for
// each PDU accepted. A broken invariant aborts. Returns true if the decoder accepted the whole
// datagram as one PDU.
bool DecodeOne(const uint8_t* data, size_t size);

inline constexpr uint8_t kFuzzExercise = 5;

}  // namespace dt::dis::fuzz
