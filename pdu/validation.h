// PDU validation: decode received bytes and check every field before anything may use them.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "pdu/pdu_traits.h"

namespace dt {

// Why a received PDU was dropped. Append, never renumber (counters are reported by index).
enum class RejectReason : uint8_t {
  kOversized,             // more than kMaxPduBytes bytes
  kTruncated,             // fewer bytes than the type needs (or an impossible array length)
  kWrongFingerprint,      // the first 8 bytes are not this type's LCM fingerprint
  kTrailingBytes,         // bytes left over after the PDU
  kWrongProtocolVersion,  // header.protocol_version != kProtocolVersion
  kForeignExercise,       // header.exercise_id is another exercise's
  kUnknownPduType,        // header.pdu_type names no PDU type
  kPduTypeMismatch,       // header.pdu_type names another PDU type than the channel's
  kUnknownFeatureType,    // feature_type names no FeatureType
  kUnknownMaterial,       // material names no Material
  kNotFinite,             // a NaN or infinity in a real-valued field
  kOutOfRange,            // sizes <= 0 or beyond the documented maxima (ValidateFeatureParams)
  kOffTerrain,            // position outside [0, terrain size] on x or z
  kBadField,              // a counter, enumeration or flag outside its range
  kInvertedRange,         // playback or anti-entropy start > end
  kHugeRange,             // playback range longer than kMaxPlaybackSpan (copies: kMaxCopySpan)
  // Authentication (pdu/pdu_auth.h), checked before any of the above:
  kUnauthenticated,  // no authentication trailer (sent without the exercise key, or not by us)
  kBadMac,           // the trailer's MAC is not the exercise key's MAC of the bytes
  kSenderMismatch,   // the trailer's sender is not the PDU's sender field
  kReplayed,         // an older incarnation of the sender, or a sequence seen or out of the window
  kStale,            // send time further from the receiver's clock than the tolerance
  // VehicleState (pdu/vehicle_state.h):
  kUnknownEntityType,  // an entity type no vehicle type of the exercise has
};
inline constexpr size_t kRejectReasonCount = 22;
static_assert(static_cast<size_t>(RejectReason::kUnknownEntityType) + 1 == kRejectReasonCount);

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

// VehicleState limits beyond which a value is absurd for every vehicle type (out_of_range). A
// vehicle type may not declare a top speed above the first (vehicle/dead_reckoning.cc checks).
inline constexpr double kMaxVehicleStateSpeedMps = 300.0;
inline constexpr double kMaxVehicleAccelerationMps2 = 200.0;
inline constexpr double kMaxVehicleAngularRateRadS = 20.0;
inline constexpr double kMaxVehicleAltitudeM = 10000.0;  // |location y|

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
