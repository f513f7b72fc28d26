// PDU validation: decode received bytes and check every field before anything may use them.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "base/enum_list.h"
#include "pdu/pdu_traits.h"

namespace dt {

// Why a received PDU was dropped: one X(enumerator, value, name) each (base/enum_list.h), the
// name as used in logs and reports. Append, never renumber (counters are reported by index).
#define DT_REJECT_REASONS(X)                                                        \
  /* more than kMaxPduBytes bytes */                                                \
  X(kOversized, 0, "oversized")                                                     \
  /* fewer bytes than the type needs (or an impossible array length) */             \
  X(kTruncated, 1, "truncated")                                                     \
  /* the first 8 bytes are not this type's LCM fingerprint */                       \
  X(kWrongFingerprint, 2, "wrong_fingerprint")                                      \
  /* bytes left over after the PDU */                                               \
  X(kTrailingBytes, 3, "trailing_bytes")                                            \
  /* header.protocol_version != kProtocolVersion */                                 \
  X(kWrongProtocolVersion, 4, "wrong_protocol")                                     \
  /* header.exercise_id is another exercise's */                                    \
  X(kForeignExercise, 5, "foreign_exercise")                                        \
  /* header.pdu_type names no PDU type */                                           \
  X(kUnknownPduType, 6, "unknown_pdu_type")                                         \
  /* header.pdu_type names another PDU type than the channel's */                   \
  X(kPduTypeMismatch, 7, "pdu_type_mismatch")                                       \
  /* feature_type names no FeatureType */                                           \
  X(kUnknownFeatureType, 8, "unknown_feature")                                      \
  /* material names no Material */                                                  \
  X(kUnknownMaterial, 9, "unknown_material")                                        \
  /* a NaN or infinity in a real-valued field */                                    \
  X(kNotFinite, 10, "not_finite")                                                   \
  /* sizes <= 0 or beyond the documented maxima (ValidateFeatureParams) */          \
  X(kOutOfRange, 11, "out_of_range")                                                \
  /* position outside [0, terrain size] on x or z */                                \
  X(kOffTerrain, 12, "off_terrain")                                                 \
  /* a counter, enumeration or flag outside its range */                            \
  X(kBadField, 13, "bad_field")                                                     \
  /* playback or anti-entropy start > end */                                        \
  X(kInvertedRange, 14, "inverted_range")                                           \
  /* playback range longer than kMaxPlaybackSpan (copies: kMaxCopySpan) */          \
  X(kHugeRange, 15, "huge_range")                                                   \
  /* Authentication (pdu/pdu_auth.h), checked before any of the above: */           \
  /* no authentication trailer (sent without the exercise key, or not by us) */     \
  X(kUnauthenticated, 16, "unauthenticated")                                        \
  /* the trailer's MAC is not the exercise key's MAC of the bytes */                \
  X(kBadMac, 17, "bad_mac")                                                         \
  /* the trailer's sender is not the PDU's sender field */                          \
  X(kSenderMismatch, 18, "sender_mismatch")                                         \
  /* an older incarnation of the sender, or a sequence seen or out of the window */ \
  X(kReplayed, 19, "replayed")                                                      \
  /* send time further from the receiver's clock than the tolerance */              \
  X(kStale, 20, "stale")                                                            \
  /* VehicleState (pdu/vehicle_state.h): */                                         \
  /* an entity type no vehicle type of the exercise has */                          \
  X(kUnknownEntityType, 21, "unknown_entity_type")

enum class RejectReason : uint8_t { DT_REJECT_REASONS(DT_ENUM_ENUMERATOR) };

inline constexpr size_t kRejectReasonCount = 0 DT_REJECT_REASONS(DT_ENUM_PLUS_ONE);
// Values run 0, 1, 2, ... in the list's order, so a value indexes the counters and the names.
static_assert(EnumValuesRunOn({DT_REJECT_REASONS(DT_ENUM_VALUE)}, 0));

// "oversized", "truncated", ... as used in logs and reports.
std::string_view RejectReasonName(RejectReason reason);

struct Rejection {
  RejectReason reason;
  std::string detail;  // names the field and its value
};

// What a receiver checks PDUs against.
struct ValidationContext {
  uint8_t exercise_id = 0;
  // The terrain covers [0, terrain_size_x_m] x [0, terrain_size_z_m].
  double terrain_size_x_m = 0.0;
  double terrain_size_z_m = 0.0;
  // Posts along x and along z: an EarthMove's posts must lie on the grid (0: only checked against
  // the largest grid, kMaxPostsPerSide; Terrain::Add checks the rest).
  int terrain_posts_x = 0;
  int terrain_posts_z = 0;
};

// Checks a decoded PDU; nullopt if it may be used.
std::optional<Rejection> Validate(const dtpdu::construct_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::update_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::destruct_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::max_feature_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::playback_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::anti_entropy_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::vehicle_state_t& pdu, const ValidationContext& ctx);
std::optional<Rejection> Validate(const dtpdu::earth_move_t& pdu, const ValidationContext& ctx);
// The batch itself: header, member count, member types. Its members: DecodeBatch (pdu/batch.h).
std::optional<Rejection> Validate(const dtpdu::batch_t& pdu, const ValidationContext& ctx);

// VehicleState limits beyond which a value is absurd for every vehicle type (out_of_range). A
// vehicle type may not declare a top speed above the first (vehicle/dead_reckoning.cc checks).
inline constexpr double kMaxVehicleStateSpeedMps = 300.0;
inline constexpr double kMaxVehicleAccelerationMps2 = 200.0;
inline constexpr double kMaxVehicleAngularRateRadS = 20.0;
inline constexpr double kMaxVehicleAltitudeM = 10000.0;  // |location y|

// Member `index` (0-based) of a batch of `count`: its pdu_type must be a PDU type other than a
// batch, its encoding whole (0) or a delta (1), and the first member whole (a delta needs the
// member before it). Validate(batch_t) and DecodeBatch (which reads a batch in place) check each
// member so.
std::optional<Rejection> CheckBatchMember(size_t index, size_t count, uint8_t pdu_type,
                                          uint8_t encoding);
// What DecodePdu checks around the decoding itself, for a decoder that reads a PDU in place: the
// size limit and the 8-byte fingerprint before; after, that the decoder read every byte
// (`decoded`: the bytes it read, negative if they did not hold the PDU).
std::optional<Rejection> CheckPduEnvelope(std::span<const uint8_t> bytes, uint64_t fingerprint);
std::optional<Rejection> CheckPduDecoded(size_t size, int decoded, PduType type);

// Decodes bytes as Pdu without validating fields: size limit, fingerprint, truncation, trailing
// bytes. Never throws and never crashes on any input.
template <AnyPdu Pdu>
std::optional<Rejection> DecodePdu(std::span<const uint8_t> bytes, Pdu& out);

// DecodePdu then Validate: `out` may be used only when this returns nullopt.
template <AnyPdu Pdu>
std::optional<Rejection> DecodeAndValidate(std::span<const uint8_t> bytes,
                                           const ValidationContext& ctx, Pdu& out) {
  if (auto r = DecodePdu(bytes, out)) return r;
  return Validate(out, ctx);
}

// Rejections counted per reason.
class RejectCounters {
 public:
  void Add(RejectReason reason) { ++counts_[static_cast<size_t>(reason)]; }
  uint64_t count(RejectReason reason) const { return counts_[static_cast<size_t>(reason)]; }
  uint64_t total() const;

 private:
  std::array<uint64_t, kRejectReasonCount> counts_{};
};

// Counts rejections and logs them (DT_LOG_WARN) at most once per interval per reason, with the
// number suppressed since the last line, so a flood of bad PDUs cannot flood the log.
class RejectLog {
 public:
  using Clock = std::chrono::steady_clock;
  explicit RejectLog(std::chrono::milliseconds interval = std::chrono::milliseconds(1000))
      : interval_(interval) {}

  // Counts the rejection and logs it unless its reason was logged less than an interval ago.
  // Returns true if a line was written.
  bool Record(PduType channel, const Rejection& rejection, Clock::time_point now = Clock::now());

  const RejectCounters& counters() const { return counters_; }

 private:
  std::chrono::milliseconds interval_;
  RejectCounters counters_;
  std::array<std::optional<Clock::time_point>, kRejectReasonCount> last_logged_{};
  std::array<uint64_t, kRejectReasonCount> suppressed_{};
};

}  // namespace dt
