#include "pdu/validation.h"

#include <cmath>
#include <exception>
#include <iterator>
#include <tuple>

#include <fmt/format.h>

#include "log/log.h"
#include "pdu/conversion.h"
#include "pdu/vehicle_state.h"

namespace dt {
namespace {

Rejection Reject(RejectReason reason, std::string detail) { return {reason, std::move(detail)}; }

// The sender runs another release: its PDUs are dropped whole, never half-understood.
Rejection WrongProtocolVersion(uint8_t version) {
  return Reject(RejectReason::kWrongProtocolVersion,
                fmt::format("protocol_version {}: the sender speaks wire format {}, this process "
                            "speaks {} only (another release of dynterrain)",
                            version, version, kProtocolVersion));
}

std::optional<Rejection> CheckHeader(const dtpdu::header_t& h, PduType expected, int64_t sender_seq,
                                     const ValidationContext& ctx) {
  if (h.protocol_version != kProtocolVersion) return WrongProtocolVersion(h.protocol_version);
  if (h.exercise_id != ctx.exercise_id) {
    return Reject(
        RejectReason::kForeignExercise,
        fmt::format("exercise_id {} (this exercise is {})", h.exercise_id, ctx.exercise_id));
  }
  const auto type = PduTypeFromRaw(h.pdu_type);
  if (!type) return Reject(RejectReason::kUnknownPduType, fmt::format("pdu_type {}", h.pdu_type));
  if (*type != expected) {
    return Reject(RejectReason::kPduTypeMismatch,
                  fmt::format("pdu_type {} ({}) on the {} channel", h.pdu_type, PduTypeName(*type),
                              PduTypeName(expected)));
  }
  if (sender_seq < 1 || sender_seq > kMaxSerial) {
    return Reject(RejectReason::kBadField, fmt::format("sender_seq {}", sender_seq));
  }
  return std::nullopt;
}

std::optional<Rejection> CheckFeatureType(int16_t raw) {
  if (raw < 0 || !IsValidFeatureType(static_cast<uint16_t>(raw))) {
    return Reject(RejectReason::kUnknownFeatureType, fmt::format("feature_type {}", raw));
  }
  return std::nullopt;
}

// Construct and Update share every field and every rule.
template <typename Pdu>
std::optional<Rejection> ValidateFeature(const Pdu& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduTraits<Pdu>::kType, pdu.sender_seq, ctx)) return r;
  if (auto r = CheckFeatureType(pdu.feature_type)) return r;
  if (pdu.feature_type == static_cast<int16_t>(FeatureType::kEarthMove)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("feature_type {} (earth_move) travels only in EarthMove PDUs",
                              pdu.feature_type));
  }
  if (pdu.material < 0 || !IsValidMaterial(static_cast<uint16_t>(pdu.material))) {
    return Reject(RejectReason::kUnknownMaterial, fmt::format("material {}", pdu.material));
  }
  const std::pair<const char*, double> reals[] = {
      {"position_m[0]", pdu.position_m[0]}, {"position_m[1]", pdu.position_m[1]},
      {"position_m[2]", pdu.position_m[2]}, {"direction_rad", pdu.direction_rad},
      {"height_m[0]", pdu.height_m[0]},     {"height_m[1]", pdu.height_m[1]},
      {"length_m[0]", pdu.length_m[0]},     {"length_m[1]", pdu.length_m[1]},
      {"length_m[2]", pdu.length_m[2]},     {"width_m", pdu.width_m}};
  for (const auto& [name, v] : reals) {
    if (!std::isfinite(v)) return Reject(RejectReason::kNotFinite, fmt::format("{} = {}", name, v));
  }
  for (const auto& e : pdu.vertex_edits) {
    if (!std::isfinite(e.offset_m)) {
      return Reject(RejectReason::kNotFinite, fmt::format("vertex edit offset_m = {}", e.offset_m));
    }
  }
  for (size_t i = 0; i < pdu.points.size(); ++i) {
    const auto& q = pdu.points[i];
    for (const auto& [name, v] :
         {std::pair{"x_m", q.x_m}, std::pair{"z_m", q.z_m}, std::pair{"height_m", q.height_m},
          std::pair{"width_m", q.width_m}}) {
      if (!std::isfinite(v)) {
        return Reject(RejectReason::kNotFinite, fmt::format("points[{}].{} = {}", i, name, v));
      }
    }
  }
  auto feature = [&] {
    if constexpr (PduTraits<Pdu>::kType == PduType::kConstruct) {
      return FromConstruct(pdu);
    } else {
      return FromUpdate(pdu);
    }
  }();
  if (!feature) return Reject(RejectReason::kBadField, feature.error().message);
  const FeaturePdu& f = feature.value();
  if (PduTraits<Pdu>::kType == PduType::kConstruct && f.change.changed_by != OriginOf(f.id)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("Construct of {} created_by {}: only the origin creates a feature",
                              f.id.ToString(), f.change.changed_by.ToString()));
  }
  for (const auto& [name, v, size_m] : {std::tuple{"x", f.params.x_m, ctx.terrain_size_x_m},
                                        std::tuple{"z", f.params.z_m, ctx.terrain_size_z_m}}) {
    if (v < 0.0 || v > size_m) {
      return Reject(RejectReason::kOffTerrain,
                    fmt::format("{} = {} m is outside [0, {}] m", name, v, size_m));
    }
  }
  for (size_t i = 0; i < f.params.points.size(); ++i) {
    const FeaturePoint& q = f.params.points[i];
    for (const auto& [name, v, size_m] : {std::tuple{"x_m", q.x_m, ctx.terrain_size_x_m},
                                          std::tuple{"z_m", q.z_m, ctx.terrain_size_z_m}}) {
      if (v < 0.0 || v > size_m) {
        return Reject(RejectReason::kOffTerrain,
                      fmt::format("points[{}].{} = {} m is outside [0, {}] m", i, name, v, size_m));
      }
    }
  }
  if (auto s = ValidateFeatureParams(f.params); !s) {
    return Reject(RejectReason::kOutOfRange, s.error().message);
  }
  return std::nullopt;
}

}  // namespace

std::string_view RejectReasonName(RejectReason reason) {
  static constexpr std::string_view kNames[] = {DT_REJECT_REASONS(DT_ENUM_NAME)};
  static_assert(std::size(kNames) == kRejectReasonCount);
  const auto i = static_cast<size_t>(reason);
  return i < std::size(kNames) ? kNames[i] : "unknown";
}

std::optional<Rejection> Validate(const dtpdu::construct_t& pdu, const ValidationContext& ctx) {
  return ValidateFeature(pdu, ctx);
}

std::optional<Rejection> Validate(const dtpdu::update_t& pdu, const ValidationContext& ctx) {
  return ValidateFeature(pdu, ctx);
}

std::optional<Rejection> Validate(const dtpdu::destruct_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kDestruct, pdu.sender_seq, ctx)) return r;
  if (auto r = CheckFeatureType(pdu.feature_type)) return r;
  if (auto d = FromDestruct(pdu); !d) return Reject(RejectReason::kBadField, d.error().message);
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::earth_move_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kEarthMove, pdu.sender_seq, ctx)) return r;
  auto move = FromEarthMove(pdu);
  if (!move) return Reject(RejectReason::kBadField, move.error().message);
  const FeaturePdu& f = move.value();
  if (f.change.changed_by != OriginOf(f.id)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("EarthMove {} moved_by {}: only the origin makes an earth move",
                              f.id.ToString(), f.change.changed_by.ToString()));
  }
  if (ctx.terrain_posts_x > 0 && ctx.terrain_posts_z > 0) {
    const int last_i = pdu.first_post_i + pdu.columns - 1;
    const int last_j = pdu.first_post_j + pdu.rows - 1;
    if (last_i >= ctx.terrain_posts_x || last_j >= ctx.terrain_posts_z) {
      return Reject(
          RejectReason::kOffTerrain,
          fmt::format("posts ({}, {}) .. ({}, {}) leave the {} x {} grid", pdu.first_post_i,
                      pdu.first_post_j, last_i, last_j, ctx.terrain_posts_x, ctx.terrain_posts_z));
    }
  }
  if (auto s = ValidateFeatureParams(f.params); !s) {
    return Reject(RejectReason::kOutOfRange, s.error().message);
  }
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::max_feature_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kMaxFeature, pdu.sender_seq, ctx)) return r;
  if (pdu.max_feature_number < 0 || pdu.max_feature_number > kMaxSerial) {
    return Reject(RejectReason::kBadField,
                  fmt::format("max_feature_number {}", pdu.max_feature_number));
  }
  if (pdu.max_change_seq < 0 || pdu.max_change_seq > kMaxSerial) {
    return Reject(RejectReason::kBadField, fmt::format("max_change_seq {}", pdu.max_change_seq));
  }
  if (pdu.lamport < 0)
    return Reject(RejectReason::kBadField, fmt::format("lamport {}", pdu.lamport));
  if (!IsValidNodeRole(pdu.role)) {
    return Reject(RejectReason::kBadField, fmt::format("role {}", pdu.role));
  }
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::playback_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kPlayback, pdu.sender_seq, ctx)) return r;
  if (!IsValidPlaybackRange(pdu.range_kind)) {
    return Reject(RejectReason::kBadField, fmt::format("range_kind {}", pdu.range_kind));
  }
  if (pdu.range_complete && !pdu.is_response) {
    return Reject(RejectReason::kBadField, "range_complete set on a request");
  }
  for (const auto& [name, v] : {std::pair{"start", pdu.start}, std::pair{"end", pdu.end}}) {
    if (v < 1 || v > kMaxSerial) {
      return Reject(RejectReason::kBadField,
                    fmt::format("playback {} {} is outside [1, {}]", name, v, kMaxSerial));
    }
  }
  if (pdu.start > pdu.end) {
    return Reject(RejectReason::kInvertedRange,
                  fmt::format("playback start {} > end {}", pdu.start, pdu.end));
  }
  if (pdu.end - pdu.start + 1 > kMaxPlaybackSpan) {
    return Reject(RejectReason::kHugeRange,
                  fmt::format("playback range {}..{} spans {} > {}", pdu.start, pdu.end,
                              pdu.end - pdu.start + 1, kMaxPlaybackSpan));
  }
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::anti_entropy_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kAntiEntropy, pdu.sender_seq, ctx)) return r;
  if (!IsValidAntiEntropyKind(pdu.kind)) {
    return Reject(RejectReason::kBadField, fmt::format("anti-entropy kind {}", pdu.kind));
  }
  if (!IsValidAntiEntropyRole(pdu.role)) {
    return Reject(RejectReason::kBadField, fmt::format("role {}", pdu.role));
  }
  if (pdu.num_entries != static_cast<int64_t>(pdu.entries.size()) ||
      pdu.num_hashes != static_cast<int64_t>(pdu.hashes.size())) {
    return Reject(
        RejectReason::kBadField,
        fmt::format("num_entries {} / num_hashes {} for {} entries and {} hashes", pdu.num_entries,
                    pdu.num_hashes, pdu.entries.size(), pdu.hashes.size()));
  }
  const auto kind = static_cast<AntiEntropyKind>(pdu.kind);
  // Every field a kind does not use must be zero, so each kind has one encoding.
  const bool is_summary = kind == AntiEntropyKind::kSummary;
  const bool is_copies = kind == AntiEntropyKind::kCopies;
  const bool is_answer = kind == AntiEntropyKind::kHashAnswer;
  if (!is_summary && pdu.num_entries != 0) {
    return Reject(RejectReason::kBadField,
                  fmt::format("{} entries outside a summary", pdu.num_entries));
  }
  if (!is_answer && !is_copies && pdu.num_hashes != 0) {
    return Reject(RejectReason::kBadField,
                  fmt::format("{} hashes in anti-entropy kind {}", pdu.num_hashes, pdu.kind));
  }
  if (pdu.exchange && kind != AntiEntropyKind::kCopyRequest) {
    return Reject(RejectReason::kBadField, "exchange set outside a copy request");
  }
  if (is_summary) {
    const dtpdu::node_address_t none{};
    if (pdu.start != 0 || pdu.end != 0 || pdu.target.site != none.site ||
        pdu.target.host != none.host || pdu.subject.site != none.site ||
        pdu.subject.host != none.host) {
      return Reject(
          RejectReason::kBadField,
          fmt::format("summary with target, subject or range {}..{}", pdu.start, pdu.end));
    }
    if (pdu.num_entries < 0 || pdu.num_entries > kMaxSummaryAuthors) {
      return Reject(RejectReason::kBadField, fmt::format("summary of {} authors (at most {})",
                                                         pdu.num_entries, kMaxSummaryAuthors));
    }
    for (const auto& e : pdu.entries) {
      if (e.seq < 0 || e.seq > kMaxSerial) {
        return Reject(RejectReason::kBadField,
                      fmt::format("summary seq {} is outside [0, {}]", e.seq, kMaxSerial));
      }
      if (e.max_held < std::max<int64_t>(e.seq, 1) || e.max_held > kMaxSerial) {
        return Reject(RejectReason::kBadField,
                      fmt::format("summary max_held {} is outside [max(seq {}, 1), {}]", e.max_held,
                                  e.seq, kMaxSerial));
      }
      if (e.seq == 0 && e.prefix_hash != 0) {
        return Reject(RejectReason::kBadField,
                      fmt::format("summary prefix_hash {} of an empty prefix", e.prefix_hash));
      }
    }
    return std::nullopt;
  }
  for (const auto& [name, v] : {std::pair{"start", pdu.start}, std::pair{"end", pdu.end}}) {
    if (v < 1 || v > kMaxSerial) {
      return Reject(RejectReason::kBadField,
                    fmt::format("anti-entropy {} {} is outside [1, {}]", name, v, kMaxSerial));
    }
  }
  if (pdu.start > pdu.end) {
    return Reject(RejectReason::kInvertedRange,
                  fmt::format("anti-entropy start {} > end {}", pdu.start, pdu.end));
  }
  if ((kind == AntiEntropyKind::kCopyRequest || is_copies) &&
      pdu.end - pdu.start + 1 > kMaxCopySpan) {
    return Reject(RejectReason::kHugeRange,
                  fmt::format("copies of {}..{} span {} > {}", pdu.start, pdu.end,
                              pdu.end - pdu.start + 1, kMaxCopySpan));
  }
  if (is_copies && pdu.num_hashes != pdu.end - pdu.start + 1) {
    return Reject(RejectReason::kBadField, fmt::format("{} hashes for copies of {}..{}",
                                                       pdu.num_hashes, pdu.start, pdu.end));
  }
  if (is_answer && pdu.num_hashes != 0 &&
      pdu.num_hashes != AntiEntropyBucketCount(pdu.start, pdu.end)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("{} hashes for {}..{} ({} buckets)", pdu.num_hashes, pdu.start,
                              pdu.end, AntiEntropyBucketCount(pdu.start, pdu.end)));
  }
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::vehicle_state_t& pdu, const ValidationContext& ctx) {
  if (auto r = CheckHeader(pdu.header, PduType::kVehicleState, pdu.sender_seq, ctx)) return r;
  if (pdu.entity_id.entity < 1 || pdu.entity_id.entity > 65535) {
    return Reject(RejectReason::kBadField,
                  fmt::format("entity number {} is outside [1, 65535]", pdu.entity_id.entity));
  }
  if (pdu.force_id > kMaxForceId) {
    return Reject(RejectReason::kBadField, fmt::format("force_id {}", pdu.force_id));
  }
  const VehicleStateFields s = FromVehicleState(pdu);
  if (VehicleNameOfEntityType(s.type).empty()) {
    return Reject(RejectReason::kUnknownEntityType,
                  fmt::format("entity type {} of entity {}", s.type.ToString(), s.id.ToString()));
  }
  const char* const axes[3] = {"[0]", "[1]", "[2]"};
  const std::pair<const char*, const double*> vectors[] = {
      {"location_m", pdu.location_m},
      {"linear_velocity_mps", pdu.linear_velocity_mps},
      {"orientation_rad", pdu.orientation_rad},
      {"linear_acceleration_mps2", pdu.linear_acceleration_mps2},
      {"angular_velocity_rad_s", pdu.angular_velocity_rad_s}};
  for (const auto& [name, v] : vectors) {
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(v[i])) {
        return Reject(RejectReason::kNotFinite, fmt::format("{}{} = {}", name, axes[i], v[i]));
      }
    }
  }
  auto norm = [](const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  if (const double speed = norm(pdu.linear_velocity_mps); speed > kMaxVehicleStateSpeedMps) {
    return Reject(RejectReason::kOutOfRange,
                  fmt::format("speed {} m/s of entity {} is beyond any vehicle type's {} m/s",
                              speed, s.id.ToString(), kMaxVehicleStateSpeedMps));
  }
  if (const double a = norm(pdu.linear_acceleration_mps2); a > kMaxVehicleAccelerationMps2) {
    return Reject(RejectReason::kOutOfRange,
                  fmt::format("acceleration {} m/s^2 > {} m/s^2", a, kMaxVehicleAccelerationMps2));
  }
  if (const double w = norm(pdu.angular_velocity_rad_s); w > kMaxVehicleAngularRateRadS) {
    return Reject(RejectReason::kOutOfRange, fmt::format("angular velocity {} rad/s > {} rad/s", w,
                                                         kMaxVehicleAngularRateRadS));
  }
  constexpr double kTwoPi = 6.283185307179586;
  constexpr double kPi = kTwoPi / 2;
  if (std::abs(s.heading_rad) > kTwoPi || std::abs(s.pitch_rad) > kPi ||
      std::abs(s.roll_rad) > kPi) {
    return Reject(RejectReason::kOutOfRange,
                  fmt::format("orientation ({}, {}, {}) rad: heading beyond one turn either way, "
                              "or pitch or roll beyond half a turn",
                              s.heading_rad, s.pitch_rad, s.roll_rad));
  }
  for (const auto& [name, v, size_m] : {std::tuple{"x", s.location_m[0], ctx.terrain_size_x_m},
                                        std::tuple{"z", s.location_m[2], ctx.terrain_size_z_m}}) {
    if (v < 0.0 || v > size_m) {
      return Reject(RejectReason::kOffTerrain,
                    fmt::format("entity {} at {} = {} m is outside [0, {}] m", s.id.ToString(),
                                name, v, size_m));
    }
  }
  if (std::abs(s.location_m[1]) > kMaxVehicleAltitudeM) {
    return Reject(RejectReason::kOutOfRange,
                  fmt::format("y = {} m is beyond +-{} m", s.location_m[1], kMaxVehicleAltitudeM));
  }
  if ((s.appearance & ~appearance::kKnown) != 0) {
    return Reject(RejectReason::kBadField,
                  fmt::format("appearance {:#010x} has bits outside {:#010x}", s.appearance,
                              appearance::kKnown));
  }
  if (!IsValidDeadReckoningAlgorithm(pdu.dead_reckoning_algorithm)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("dead_reckoning_algorithm {}", pdu.dead_reckoning_algorithm));
  }
  if (pdu.marking_charset != kMarkingAscii) {
    return Reject(RejectReason::kBadField,
                  fmt::format("marking_charset {} (only 1, ASCII)", pdu.marking_charset));
  }
  // Printable characters, then NULs only: one encoding per marking.
  bool ended = false;
  for (size_t i = 0; i < kMarkingChars; ++i) {
    const uint8_t c = pdu.marking[i];
    if (c == 0) {
      ended = true;
    } else if (ended || c < 32 || c > 126) {
      return Reject(RejectReason::kBadField, fmt::format("marking byte {} is {:#04x}", i, c));
    }
  }
  return std::nullopt;
}

std::optional<Rejection> Validate(const dtpdu::batch_t& pdu, const ValidationContext& ctx) {
  // A batch has no sender_seq of its own (its members have), so 1 passes the header's check.
  if (auto r = CheckHeader(pdu.header, PduType::kBatch, 1, ctx)) return r;
  if (pdu.num_members < 1) {
    return Reject(RejectReason::kBadField, fmt::format("num_members {}", pdu.num_members));
  }
  for (size_t i = 0; i < pdu.members.size(); ++i) {
    const auto& m = pdu.members[i];
    if (auto r = CheckBatchMember(i, pdu.members.size(), m.pdu_type, m.encoding)) return r;
  }
  return std::nullopt;
}

std::optional<Rejection> CheckBatchMember(size_t index, size_t count, uint8_t pdu_type,
                                          uint8_t encoding) {
  const auto type = PduTypeFromRaw(pdu_type);
  if (!type || *type == PduType::kBatch) {
    return Reject(RejectReason::kUnknownPduType,
                  fmt::format("member {} of {}: pdu_type {}", index + 1, count, pdu_type));
  }
  // Values of MemberEncoding (pdu/member_delta.h, which builds on this file): 0 whole, 1 delta.
  if (encoding > 1 || (encoding == 1 && index == 0)) {
    return Reject(RejectReason::kBadField,
                  fmt::format("member {} of {}: encoding {}{}", index + 1, count, encoding,
                              encoding > 1 ? "" : " (a delta needs a member before it)"));
  }
  return std::nullopt;
}

std::optional<Rejection> CheckPduEnvelope(std::span<const uint8_t> bytes, uint64_t fingerprint) {
  if (bytes.size() > kMaxPduBytes) {
    return Reject(RejectReason::kOversized,
                  fmt::format("{} bytes > {}", bytes.size(), kMaxPduBytes));
  }
  if (bytes.size() < 8) {
    return Reject(RejectReason::kTruncated, fmt::format("{} bytes, no fingerprint", bytes.size()));
  }
  uint64_t got = 0;
  for (size_t i = 0; i < 8; ++i) got = (got << 8) | bytes[i];
  if (got != fingerprint) {
    // An earlier release's layout of this type (the batch of version 3 had members without an
    // encoding) has another fingerprint; its header, right after, still names its version.
    if (bytes.size() > 8 && bytes[8] >= 1 && bytes[8] < kProtocolVersion) {
      return WrongProtocolVersion(bytes[8]);
    }
    return Reject(RejectReason::kWrongFingerprint,
                  fmt::format("fingerprint {:#018x} (expected {:#018x})", got, fingerprint));
  }
  return std::nullopt;
}

std::optional<Rejection> CheckPduDecoded(size_t size, int decoded, PduType type) {
  if (decoded < 0) {
    return Reject(RejectReason::kTruncated,
                  fmt::format("{} bytes do not hold a {} PDU", size, PduTypeName(type)));
  }
  if (static_cast<size_t>(decoded) != size) {
    return Reject(RejectReason::kTrailingBytes,
                  fmt::format("{} bytes after a {}-byte PDU", size - decoded, decoded));
  }
  return std::nullopt;
}

template <AnyPdu Pdu>
std::optional<Rejection> DecodePdu(std::span<const uint8_t> bytes, Pdu& out) {
  if (auto r = CheckPduEnvelope(bytes, static_cast<uint64_t>(Pdu::getHash()))) return r;
  int n = -1;
  try {
    out = Pdu{};
    n = out.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
  } catch (const std::exception&) {
    // LCM resizes arrays from the received length field first: a negative one throws.
    n = -1;
  }
  return CheckPduDecoded(bytes.size(), n, PduTraits<Pdu>::kType);
}

template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::construct_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::update_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::destruct_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::max_feature_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::playback_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::anti_entropy_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::vehicle_state_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::earth_move_t&);
template std::optional<Rejection> DecodePdu(std::span<const uint8_t>, dtpdu::batch_t&);

uint64_t RejectCounters::total() const {
  uint64_t sum = 0;
  for (uint64_t c : counts_) sum += c;
  return sum;
}

bool RejectLog::Record(PduType channel, const Rejection& rejection, Clock::time_point now) {
  counters_.Add(rejection.reason);
  const auto i = static_cast<size_t>(rejection.reason);
  if (last_logged_[i] && now - *last_logged_[i] < interval_) {
    ++suppressed_[i];
    return false;
  }
  DT_LOG_WARN("dropped a {} PDU: {} ({}); {} more {} since the last such line",
              PduTypeName(channel), RejectReasonName(rejection.reason), rejection.detail,
              suppressed_[i], RejectReasonName(rejection.reason));
  last_logged_[i] = now;
  suppressed_[i] = 0;
  return true;
}

}  // namespace dt
