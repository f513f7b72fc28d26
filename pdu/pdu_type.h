// PduType and the protocol constants: PDU type values, channel names, size and range limits.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace dt {

// Version of the PDU layout carried in every header; a receiver drops any other version.
inline constexpr uint8_t kProtocolVersion = 1;

// Wire values of header.pdu_type. DIS reserves 129..255 for experimental PDUs; 220..224 keep
// clear of standard DIS traffic. Append, never renumber.
enum class PduType : uint8_t {
  kConstruct = 220,
  kUpdate = 221,
  kDestruct = 222,
  kMaxFeature = 223,
  kPlayback = 224,
};

inline constexpr std::array<PduType, 5> kAllPduTypes = {PduType::kConstruct, PduType::kUpdate,
                                                        PduType::kDestruct, PduType::kMaxFeature,
                                                        PduType::kPlayback};

// "CONSTRUCT", "UPDATE", "DESTRUCT", "MAXFEATURE", "PLAYBACK".
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
enum class NodeRole : uint8_t { kNode = 0, kServer = 1, kStandby = 2 };
inline bool IsServerRole(NodeRole r) { return r == NodeRole::kServer || r == NodeRole::kStandby; }
inline bool IsValidNodeRole(uint8_t raw) { return raw <= 2; }
// "node", "server", "standby" ("unknown" for a value outside the enum).
std::string_view NodeRoleName(NodeRole role);

// What a Playback PDU's start and end count.
enum class PlaybackRange : uint8_t { kFeatureNumbers = 0, kChangeSeqs = 1 };
inline bool IsValidPlaybackRange(uint8_t raw) { return raw <= 1; }

// A Playback request covers at most this many numbers (end - start + 1); bigger ones are dropped
// as "huge", and requesters split their ranges.
inline constexpr int64_t kMaxPlaybackSpan = 65536;

// Highest feature number, change_seq and sender_seq a PDU may carry (32-bit unsigned).
inline constexpr int64_t kMaxSerial = 4294967295;

// Most crater vertex edits one PDU carries (16 spokes x 4 rings).
inline constexpr int kMaxVertexEdits = 64;

}  // namespace dt
