// ChangeHash: a change's canonical bytes and their 64-bit hash, which anti-entropy sums over logs.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/change.h"

namespace dt {

// Kind, feature ID, stamp (author, change_seq, lamport) and parameters (a Destruct: its type
// only; the parameters as EncodeFeatureParams lays them out), little-endian: equal changes, and
// only they, give equal bytes. The stamp is included, so the same edit in two slots hashes
// differently and a sum over a range sees which slot holds what.
std::vector<uint8_t> CanonicalChangeBytes(const Change& change);

// XXH3-64 of CanonicalChangeBytes.
uint64_t ChangeHash(const Change& change);

}  // namespace dt
