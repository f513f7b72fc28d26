// PduType and the protocol constants: PDU type values, channel names, size and range limits.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace dt {

// Version of the PDU layout carried in every header; a receiver drops any other version.
// 2: the EarthMove PDU (226); a node of version 1 would miss blade work and stall on the change
// numbers it takes, so the versions do not mix.
// 3: the Batch PDU (231): a node of version 2 hears no batch, so it would miss most changes.
// 4: batch members as deltas (batch_member_t.encoding): a node of version 3 cannot read a batch.
inline constexpr uint8_t kProtocolVersion = 4;

// Wire values of header.pdu_type. DIS reserves 129..255 for experimental PDUs; 220..225 keep
// clear of standard DIS traffic, and 226 follows them. Append, never renumber.
enum class PduType : uint8_t {
  kConstruct = 220,
  kUpdate = 221,
  kDestruct = 222,
  kMaxFeature = 223,
  kPlayback = 224,
  kAntiEntropy = 225,
  kEarthMove = 226,  // blade work: additive post height changes (docs/pdu.md "EarthMove")
  // Shared vehicles (docs/pdu.md "VehicleState"); 226..229 are left to terrain PDUs.
  kVehicleState = 230,
  // Several PDUs of one sender in one datagram (docs/pdu.md "Batch"); never a member of one.
  kBatch = 231,
};

inline constexpr std::array<PduType, 9> kAllPduTypes = {
    PduType::kConstruct,    PduType::kUpdate,    PduType::kDestruct,
    PduType::kMaxFeature,   PduType::kPlayback,  PduType::kAntiEntropy,
    PduType::kVehicleState, PduType::kEarthMove, PduType::kBatch};

// "CONSTRUCT", "UPDATE", "DESTRUCT", "MAXFEATURE", "PLAYBACK", "ANTIENTROPY", "VEHICLESTATE",
// "EARTHMOVE", "BATCH".
std::string_view PduTypeName(PduType type);
// The PduType with this wire value; nullopt if it names none.
std::optional<PduType> PduTypeFromRaw(uint8_t raw);

// The channel (LCM) or topic (DDS) of a PDU type in an exercise: "DT<exercise>_<NAME>", so two
// exercises on one host never see each other's traffic.
std::string ChannelName(uint8_t exercise_id, PduType type);

// Every PDU travels in one datagram of one Ethernet frame: publishing bigger bytes is refused,
// and receivers drop them.
inline constexpr size_t kMaxPduBytes = 1400;

// Role carried by MaxFeature PDUs.
// kObserver: a live view (docs/view.md). It sends no MaxFeature; its anti-entropy requests carry
// the role so that peers answer them without counting it as a holder (engine/replica.h).
enum class NodeRole : uint8_t { kNode = 0, kServer = 1, kStandby = 2, kObserver = 3 };
inline bool IsServerRole(NodeRole r) { return r == NodeRole::kServer || r == NodeRole::kStandby; }
// MaxFeature: node, server or standby (an observer sends none). AntiEntropy: any of the four.
inline bool IsValidNodeRole(uint8_t raw) { return raw <= 2; }
inline bool IsValidAntiEntropyRole(uint8_t raw) { return raw <= 3; }
// "node", "server", "standby", "observer" ("unknown" for a value outside the enum).
std::string_view NodeRoleName(NodeRole role);

// What a Playback PDU's start and end count.
enum class PlaybackRange : uint8_t { kFeatureNumbers = 0, kChangeSeqs = 1 };
inline bool IsValidPlaybackRange(uint8_t raw) { return raw <= 1; }

// A Playback request covers at most this many numbers (end - start + 1); bigger ones are dropped
// as "huge", and requesters split their ranges.
inline constexpr int64_t kMaxPlaybackSpan = 65536;

// What an AntiEntropy PDU is (docs/protocol.md, "Anti-entropy").
enum class AntiEntropyKind : uint8_t {
  kSummary = 0,      // per author: gap-free point and prefix hash
  kHashRequest = 1,  // "send me the bucket hashes of subject's [start, end]"
  kHashAnswer = 2,   // those hashes
  kCopyRequest = 3,  // "send me your copies of subject's [start, end]"
  kCopies = 4,       // follows the copies sent, with the hash of each
};
inline bool IsValidAntiEntropyKind(uint8_t raw) { return raw <= 4; }

// Authors in one summary (28 bytes each: the PDU stays under kMaxPduBytes with the
// authentication trailer, pdu/test/validation_test.cc); a replica holding more sends several.
inline constexpr int kMaxSummaryAuthors = 40;
// A hash request's range is split into at most this many buckets, so a difference in a log of n
// changes is located in ceil(log_32 n) rounds.
inline constexpr int64_t kAntiEntropyBuckets = 32;
// The buckets of [start, end] (start <= end): min(kAntiEntropyBuckets, end - start + 1).
inline int64_t AntiEntropyBucketCount(int64_t start, int64_t end) {
  return end - start + 1 < kAntiEntropyBuckets ? end - start + 1 : kAntiEntropyBuckets;
}
// Bucket `index` (0-based) of [start, end] as {first, last}: the range cut into
// AntiEntropyBucketCount near-equal consecutive pieces, the same on every replica.
inline std::pair<int64_t, int64_t> HashBucket(int64_t start, int64_t end, int64_t index) {
  const int64_t n = end - start + 1;
  const int64_t k = AntiEntropyBucketCount(start, end);
  return {start + n * index / k, start + n * (index + 1) / k - 1};
}
// A copy request (and the copies that answer it) covers at most this many change sequences, so
// a request of one datagram cannot ask for an unbounded answer.
inline constexpr int64_t kMaxCopySpan = kAntiEntropyBuckets;

// Highest feature number, change_seq and sender_seq a PDU may carry (32-bit unsigned).
inline constexpr int64_t kMaxSerial = 4294967295;

// Most crater vertex edits one PDU carries (16 spokes x 4 rings).
inline constexpr int kMaxVertexEdits = 64;

}  // namespace dt
