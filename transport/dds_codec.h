// DDS codec: each PDU type's IDL sample, converted from and to its LCM encoding; the IDL and the
// conversions are generated from pdu/lcm/*.lcm by transport/idl/lcm_to_idl.py.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <dds/dds.h>

#include "base/result.h"
#include "pdu/pdu_type.h"

namespace dt::dds_codec {

// Bytes after the LCM-encoded PDU (an authentication trailer added above the transport) travel in
// the sample's `auth` member, at most this many.
inline constexpr size_t kMaxAuthBytes = 128;

// The IDL type of `type`'s topic (dtpdu_dds::<lcm name>).
const dds_topic_descriptor_t* Descriptor(PduType type);

// Decodes `bytes` (an LCM-encoded `type` PDU, then at most kMaxAuthBytes more) into the IDL sample
// and writes it with `writer`. Error: the bytes are no such PDU (the message says why), or the
// dds_write return code's name (e.g. "Timeout": nothing was written).
Status Write(PduType type, dds_entity_t writer, std::span<const uint8_t> bytes);

// Re-encodes a received `type` sample as the LCM bytes it was written from (LCM's encoding is
// deterministic), its `auth` bytes appended, into `bytes`. False if the sample is inconsistent
// (a sequence whose length disagrees with its LCM length member).
bool Read(PduType type, const void* sample, std::vector<uint8_t>& bytes);

}  // namespace dt::dds_codec
