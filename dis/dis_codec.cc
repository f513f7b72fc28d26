#include "dis/dis_codec.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <iterator>
#include <stdexcept>

#include "base/demand.h"
#include "dis/big_endian.h"

namespace dt::dis {
namespace {

// ---- Encoding -----------------------------------------------------------------------------

// The field writers and readers are inlined into each encoder and decoder, so the writer or
// reader never leaves it: otherwise every byte stored through a uint8_t* may alias their
// members, which are then reloaded per byte.
#define DT_FIELD_INLINE [[gnu::always_inline]] inline

// The throw out of line, so the check itself inlines into every field's write.
[[noreturn, gnu::cold, gnu::noinline]] void NotFinite(double v, const char* field) {
  throw std::invalid_argument(fmt::format("DIS encode: {} is {}", field, v));
}
void RequireFinite(float v, const char* field) {
  if (!std::isfinite(v)) [[unlikely]]
    NotFinite(v, field);
}
void RequireFinite(double v, const char* field) {
  if (!std::isfinite(v)) [[unlikely]]
    NotFinite(v, field);
}

DT_FIELD_INLINE void PutHeader(BigEndianWriter& w, const Header& h, PduType type, uint8_t family) {
  w.U8(h.protocol_version);
  w.U8(h.exercise_id);
  w.U8(static_cast<uint8_t>(type));
  w.U8(family);
  w.U32(h.timestamp);
  w.U16(0);  // length, patched once the body is written
  w.U8(h.pdu_status);
  w.U8(0);  // padding
}

void PatchLength(std::vector<uint8_t>& out) {
  if (out.size() > kMaxPduSize) {
    throw std::invalid_argument(
        fmt::format("DIS encode: PDU of {} bytes exceeds {}", out.size(), kMaxPduSize));
  }
  out[8] = static_cast<uint8_t>(out.size() >> 8);
  out[9] = static_cast<uint8_t>(out.size());
}

DT_FIELD_INLINE void PutEntityId(BigEndianWriter& w, const EntityId& id) {
  w.U16(id.site);
  w.U16(id.application);
  w.U16(id.entity);
}
DT_FIELD_INLINE void PutAddress(BigEndianWriter& w, const SimulationAddress& a) {
  w.U16(a.site);
  w.U16(a.application);
}
DT_FIELD_INLINE void PutEntityType(BigEndianWriter& w, const EntityType& t) {
  w.U8(t.kind);
  w.U8(t.domain);
  w.U16(t.country);
  w.U8(t.category);
  w.U8(t.subcategory);
  w.U8(t.specific);
  w.U8(t.extra);
}
DT_FIELD_INLINE void PutObjectType(BigEndianWriter& w, const ObjectType& t) {
  w.U8(t.domain);
  w.U8(t.kind);
  w.U8(t.category);
  w.U8(t.subcategory);
}
DT_FIELD_INLINE void PutVector(BigEndianWriter& w, const Vector3F& v, const char* field) {
  RequireFinite(v.x, field);
  RequireFinite(v.y, field);
  RequireFinite(v.z, field);
  w.F32(v.x);
  w.F32(v.y);
  w.F32(v.z);
}
DT_FIELD_INLINE void PutLocation(BigEndianWriter& w, const WorldCoordinates& c, const char* field) {
  RequireFinite(c.x, field);
  RequireFinite(c.y, field);
  RequireFinite(c.z, field);
  w.F64(c.x);
  w.F64(c.y);
  w.F64(c.z);
}
DT_FIELD_INLINE void PutAngles(BigEndianWriter& w, const EulerAngles& a, const char* field) {
  RequireFinite(a.psi, field);
  RequireFinite(a.theta, field);
  RequireFinite(a.phi, field);
  w.F32(a.psi);
  w.F32(a.theta);
  w.F32(a.phi);
}

// ---- Decoding -----------------------------------------------------------------------------

DecodeError Fail(DecodeFailure f, std::string message) { return {f, std::move(message)}; }

DT_FIELD_INLINE Header GetHeader(BigEndianReader& r) {
  Header h;
  h.protocol_version = r.U8();
  h.exercise_id = r.U8();
  h.pdu_type = r.U8();
  h.protocol_family = r.U8();
  h.timestamp = r.U32();
  h.length = r.U16();
  h.pdu_status = r.U8();
  r.Skip(1);
  return h;
}
DT_FIELD_INLINE EntityId GetEntityId(BigEndianReader& r) {
  EntityId id;
  id.site = r.U16();
  id.application = r.U16();
  id.entity = r.U16();
  return id;
}
DT_FIELD_INLINE SimulationAddress GetAddress(BigEndianReader& r) {
  SimulationAddress a;
  a.site = r.U16();
  a.application = r.U16();
  return a;
}
DT_FIELD_INLINE EntityType GetEntityType(BigEndianReader& r) {
  EntityType t;
  t.kind = r.U8();
  t.domain = r.U8();
  t.country = r.U16();
  t.category = r.U8();
  t.subcategory = r.U8();
  t.specific = r.U8();
  t.extra = r.U8();
  return t;
}
DT_FIELD_INLINE ObjectType GetObjectType(BigEndianReader& r) {
  ObjectType t;
  t.domain = r.U8();
  t.kind = r.U8();
  t.category = r.U8();
  t.subcategory = r.U8();
  return t;
}
DT_FIELD_INLINE Vector3F GetVector(BigEndianReader& r) {
  Vector3F v;
  v.x = r.F32();
  v.y = r.F32();
  v.z = r.F32();
  return v;
}
DT_FIELD_INLINE WorldCoordinates GetLocation(BigEndianReader& r) {
  WorldCoordinates c;
  c.x = r.F64();
  c.y = r.F64();
  c.z = r.F64();
  return c;
}
DT_FIELD_INLINE EulerAngles GetAngles(BigEndianReader& r) {
  EulerAngles a;
  a.psi = r.F32();
  a.theta = r.F32();
  a.phi = r.F32();
  return a;
}

// The first non-finite field among those given, by name.
struct NamedFloat {
  const char* name;
  double value;
};
std::optional<DecodeError> FirstNonFinite(std::initializer_list<NamedFloat> fields) {
  for (const NamedFloat& f : fields) {
    if (!std::isfinite(f.value)) {
      return Fail(DecodeFailure::kNonFinite, fmt::format("{} is {}", f.name, f.value));
    }
  }
  return std::nullopt;
}

// True when no float has the all-ones exponent of an infinity or NaN (no branch per field).
bool AllFinite(std::initializer_list<float> values) {
  uint32_t bad = 0;
  for (float v : values) {
    const uint32_t exponent = std::bit_cast<uint32_t>(v) & 0x7F800000u;
    bad |= static_cast<uint32_t>(exponent == 0x7F800000u);
  }
  return bad == 0;
}

DecodeResult DecodeEntityState(std::span<const uint8_t> in, const Header& h) {
  if (in.size() < kEntityStateSize) {
    return Fail(DecodeFailure::kTooShort, fmt::format("Entity State of {} bytes, needs at least {}",
                                                      in.size(), kEntityStateSize));
  }
  const uint8_t count = in[19];
  const size_t expected = kEntityStateSize + size_t{count} * kVariableParameterSize;
  if (in.size() != expected) {
    return Fail(DecodeFailure::kLengthMismatch,
                fmt::format("Entity State of {} bytes with {} variable parameters, expected {}",
                            in.size(), count, expected));
  }
  BigEndianReader r(in.subspan(kHeaderSize));
  EntityStatePdu p;
  p.header = h;
  p.entity_id = GetEntityId(r);
  p.force_id = r.U8();
  r.Skip(1);  // count, read above
  p.entity_type = GetEntityType(r);
  p.alternative_entity_type = GetEntityType(r);
  p.linear_velocity = GetVector(r);
  p.location = GetLocation(r);
  p.orientation = GetAngles(r);
  p.appearance = r.U32();
  p.dead_reckoning.algorithm = r.U8();
  r.Copy(p.dead_reckoning.other_parameters);
  p.dead_reckoning.linear_acceleration = GetVector(r);
  p.dead_reckoning.angular_velocity = GetVector(r);
  p.marking.character_set = r.U8();
  for (char& c : p.marking.characters) c = static_cast<char>(r.U8());
  p.capabilities = r.U32();
  p.variable_parameters.resize(count);
  for (VariableParameter& v : p.variable_parameters) {
    v.record_type = r.U8();
    r.Copy(v.data);
  }
  const auto& dr = p.dead_reckoning;
  // All finite is the rule: one pass without names, the named search only when one is not.
  const bool all_finite =
      AllFinite({p.linear_velocity.x, p.linear_velocity.y, p.linear_velocity.z, p.orientation.psi,
                 p.orientation.theta, p.orientation.phi, dr.linear_acceleration.x,
                 dr.linear_acceleration.y, dr.linear_acceleration.z, dr.angular_velocity.x,
                 dr.angular_velocity.y, dr.angular_velocity.z}) &&
      std::isfinite(p.location.x) && std::isfinite(p.location.y) && std::isfinite(p.location.z);
  if (!all_finite) {
    if (auto e = FirstNonFinite({{"linear velocity x", p.linear_velocity.x},
                                 {"linear velocity y", p.linear_velocity.y},
                                 {"linear velocity z", p.linear_velocity.z},
                                 {"location x", p.location.x},
                                 {"location y", p.location.y},
                                 {"location z", p.location.z},
                                 {"orientation psi", p.orientation.psi},
                                 {"orientation theta", p.orientation.theta},
                                 {"orientation phi", p.orientation.phi},
                                 {"linear acceleration x", dr.linear_acceleration.x},
                                 {"linear acceleration y", dr.linear_acceleration.y},
                                 {"linear acceleration z", dr.linear_acceleration.z},
                                 {"angular velocity x", dr.angular_velocity.x},
                                 {"angular velocity y", dr.angular_velocity.y},
                                 {"angular velocity z", dr.angular_velocity.z}})) {
      return *e;
    }
  }
  if (dr.algorithm > kMaxDeadReckoningAlgorithm) {
    return Fail(DecodeFailure::kBadField, fmt::format("dead-reckoning algorithm {} (0..{} defined)",
                                                      dr.algorithm, kMaxDeadReckoningAlgorithm));
  }
  return Pdu(std::move(p));
}

DecodeResult DecodePointObjectState(std::span<const uint8_t> in, const Header& h) {
  if (in.size() != kPointObjectStateSize) {
    return Fail(in.size() < kPointObjectStateSize ? DecodeFailure::kTooShort
                                                  : DecodeFailure::kLengthMismatch,
                fmt::format("Point Object State of {} bytes, expected {}", in.size(),
                            kPointObjectStateSize));
  }
  BigEndianReader r(in.subspan(kHeaderSize));
  PointObjectStatePdu p;
  p.header = h;
  p.object_id = GetEntityId(r);
  p.referenced_object_id = GetEntityId(r);
  p.update_number = r.U16();
  p.force_id = r.U8();
  p.modifications = r.U8();
  p.object_type = GetObjectType(r);
  p.location = GetLocation(r);
  p.orientation = GetAngles(r);
  p.specific_appearance = r.U32();
  p.general_appearance = r.U16();
  r.Skip(2);  // padding after the 48-bit appearance
  p.requester_id = GetAddress(r);
  p.receiving_id = GetAddress(r);
  r.Skip(4);  // padding
  if (auto e = FirstNonFinite({{"location x", p.location.x},
                               {"location y", p.location.y},
                               {"location z", p.location.z},
                               {"orientation psi", p.orientation.psi},
                               {"orientation theta", p.orientation.theta},
                               {"orientation phi", p.orientation.phi}})) {
    return *e;
  }
  return Pdu(std::move(p));
}

DecodeResult DecodeLinearObjectState(std::span<const uint8_t> in, const Header& h) {
  if (in.size() < kLinearObjectStateSize) {
    return Fail(DecodeFailure::kTooShort,
                fmt::format("Linear Object State of {} bytes, needs at least {}", in.size(),
                            kLinearObjectStateSize));
  }
  const uint8_t count = in[27];
  const size_t expected = kLinearObjectStateSize + size_t{count} * kLinearSegmentSize;
  if (in.size() != expected) {
    return Fail(DecodeFailure::kLengthMismatch,
                fmt::format("Linear Object State of {} bytes with {} segments, expected {}",
                            in.size(), count, expected));
  }
  BigEndianReader r(in.subspan(kHeaderSize));
  LinearObjectStatePdu p;
  p.header = h;
  p.object_id = GetEntityId(r);
  p.referenced_object_id = GetEntityId(r);
  p.update_number = r.U16();
  p.force_id = r.U8();
  r.Skip(1);  // count, read above
  p.requester_id = GetAddress(r);
  p.receiving_id = GetAddress(r);
  p.object_type = GetObjectType(r);
  p.segments.resize(count);
  for (size_t i = 0; i < p.segments.size(); ++i) {
    LinearSegment& s = p.segments[i];
    s.segment_number = r.U8();
    s.modifications = r.U8();
    s.general_appearance = r.U16();
    s.specific_appearance = r.U32();
    s.location = GetLocation(r);
    s.orientation = GetAngles(r);
    s.length_m = r.F32();
    s.width_m = r.F32();
    s.height_m = r.F32();
    s.depth_m = r.F32();
    r.Skip(4);  // padding
    if (auto e = FirstNonFinite({{"segment location x", s.location.x},
                                 {"segment location y", s.location.y},
                                 {"segment location z", s.location.z},
                                 {"segment orientation psi", s.orientation.psi},
                                 {"segment orientation theta", s.orientation.theta},
                                 {"segment orientation phi", s.orientation.phi},
                                 {"segment length", s.length_m},
                                 {"segment width", s.width_m},
                                 {"segment height", s.height_m},
                                 {"segment depth", s.depth_m}})) {
      e->message = fmt::format("segment {}: {}", i, e->message);
      return *e;
    }
  }
  return Pdu(std::move(p));
}

}  // namespace

std::vector<uint8_t> Encode(const EntityStatePdu& p) {
  std::vector<uint8_t> out;
  EncodeInto(p, out);
  return out;
}

void EncodeInto(const EntityStatePdu& p, std::vector<uint8_t>& out) {
  if (p.variable_parameters.size() > 255) {
    throw std::invalid_argument(fmt::format("DIS encode: {} variable parameters (at most 255)",
                                            p.variable_parameters.size()));
  }
  BigEndianWriter w(out, kEntityStateSize + p.variable_parameters.size() * kVariableParameterSize);
  PutHeader(w, p.header, PduType::kEntityState, kFamilyEntityInformation);
  PutEntityId(w, p.entity_id);
  w.U8(p.force_id);
  w.U8(static_cast<uint8_t>(p.variable_parameters.size()));
  PutEntityType(w, p.entity_type);
  PutEntityType(w, p.alternative_entity_type);
  PutVector(w, p.linear_velocity, "linear velocity");
  PutLocation(w, p.location, "location");
  PutAngles(w, p.orientation, "orientation");
  w.U32(p.appearance);
  w.U8(p.dead_reckoning.algorithm);
  w.Bytes(p.dead_reckoning.other_parameters);
  PutVector(w, p.dead_reckoning.linear_acceleration, "linear acceleration");
  PutVector(w, p.dead_reckoning.angular_velocity, "angular velocity");
  w.U8(p.marking.character_set);
  for (char c : p.marking.characters) w.U8(static_cast<uint8_t>(c));
  w.U32(p.capabilities);
  for (const VariableParameter& v : p.variable_parameters) {
    w.U8(v.record_type);
    w.Bytes(v.data);
  }
  DT_DEMAND(w.complete());  // else the layout's size and the fields written disagree
  PatchLength(out);
}

std::vector<uint8_t> Encode(const PointObjectStatePdu& p) {
  std::vector<uint8_t> out;
  BigEndianWriter w(out, kPointObjectStateSize);
  PutHeader(w, p.header, PduType::kPointObjectState, kFamilySyntheticEnvironment);
  PutEntityId(w, p.object_id);
  PutEntityId(w, p.referenced_object_id);
  w.U16(p.update_number);
  w.U8(p.force_id);
  w.U8(p.modifications);
  PutObjectType(w, p.object_type);
  PutLocation(w, p.location, "location");
  PutAngles(w, p.orientation, "orientation");
  w.U32(p.specific_appearance);
  w.U16(p.general_appearance);
  w.Zeros(2);
  PutAddress(w, p.requester_id);
  PutAddress(w, p.receiving_id);
  w.Zeros(4);
  DT_DEMAND(w.complete());  // else the layout's size and the fields written disagree
  PatchLength(out);
  return out;
}

std::vector<uint8_t> Encode(const LinearObjectStatePdu& p) {
  if (p.segments.size() > 255) {
    throw std::invalid_argument(
        fmt::format("DIS encode: {} linear segments (at most 255)", p.segments.size()));
  }
  std::vector<uint8_t> out;
  BigEndianWriter w(out, kLinearObjectStateSize + p.segments.size() * kLinearSegmentSize);
  PutHeader(w, p.header, PduType::kLinearObjectState, kFamilySyntheticEnvironment);
  PutEntityId(w, p.object_id);
  PutEntityId(w, p.referenced_object_id);
  w.U16(p.update_number);
  w.U8(p.force_id);
  w.U8(static_cast<uint8_t>(p.segments.size()));
  PutAddress(w, p.requester_id);
  PutAddress(w, p.receiving_id);
  PutObjectType(w, p.object_type);
  for (const LinearSegment& s : p.segments) {
    w.U8(s.segment_number);
    w.U8(s.modifications);
    w.U16(s.general_appearance);
    w.U32(s.specific_appearance);
    PutLocation(w, s.location, "segment location");
    PutAngles(w, s.orientation, "segment orientation");
    RequireFinite(s.length_m, "segment length");
    RequireFinite(s.width_m, "segment width");
    RequireFinite(s.height_m, "segment height");
    RequireFinite(s.depth_m, "segment depth");
    w.F32(s.length_m);
    w.F32(s.width_m);
    w.F32(s.height_m);
    w.F32(s.depth_m);
    w.Zeros(4);
  }
  DT_DEMAND(w.complete());  // else the layout's size and the fields written disagree
  PatchLength(out);
  return out;
}

std::string_view DecodeFailureName(DecodeFailure failure) {
  static constexpr std::string_view kNames[] = {DT_DECODE_FAILURES(DT_ENUM_NAME)};
  static_assert(std::size(kNames) == kDecodeFailureCount);
  const auto i = static_cast<size_t>(failure);
  return i < std::size(kNames) ? kNames[i] : "unknown";
}

const Pdu& DecodeResult::pdu() const {
  DT_DEMAND(ok());
  return std::get<Pdu>(v_);
}
const DecodeError& DecodeResult::error() const {
  DT_DEMAND(!ok());
  return std::get<DecodeError>(v_);
}

DecodeResult DecodePdu(std::span<const uint8_t> in, std::optional<uint8_t> exercise_id) {
  if (in.size() < kHeaderSize) {
    return Fail(DecodeFailure::kTooShort,
                fmt::format("datagram of {} bytes, a DIS header needs {}", in.size(), kHeaderSize));
  }
  if (in.size() > kMaxPduSize) {
    return Fail(
        DecodeFailure::kTooLong,
        fmt::format("datagram of {} bytes, a DIS PDU has at most {}", in.size(), kMaxPduSize));
  }
  BigEndianReader r(in);
  const Header h = GetHeader(r);
  if (h.protocol_version != kProtocolVersionDis7 && h.protocol_version != kProtocolVersionDis6) {
    return Fail(DecodeFailure::kUnsupportedVersion,
                fmt::format("protocol version {} (6 or 7 read)", h.protocol_version));
  }
  if (h.length != in.size()) {
    return Fail(DecodeFailure::kLengthMismatch,
                fmt::format("length field {} in a datagram of {} bytes", h.length, in.size()));
  }
  if (exercise_id && h.exercise_id != *exercise_id) {
    return Fail(DecodeFailure::kForeignExercise,
                fmt::format("exercise {} (this exercise is {})", h.exercise_id, *exercise_id));
  }
  uint8_t family = 0;
  switch (h.pdu_type) {
    case static_cast<uint8_t>(PduType::kEntityState):
      family = kFamilyEntityInformation;
      break;
    case static_cast<uint8_t>(PduType::kPointObjectState):
    case static_cast<uint8_t>(PduType::kLinearObjectState):
      family = kFamilySyntheticEnvironment;
      if (h.protocol_version != kProtocolVersionDis7) {
        return Fail(DecodeFailure::kUnsupportedVersion,
                    fmt::format("PDU type {} in protocol version {} (its DIS 7 layout only)",
                                h.pdu_type, h.protocol_version));
      }
      break;
    default:
      return Fail(DecodeFailure::kUnsupportedPduType, fmt::format("PDU type {}", h.pdu_type));
  }
  if (h.protocol_family != family) {
    return Fail(DecodeFailure::kFamilyMismatch,
                fmt::format("PDU type {} with protocol family {} (expected {})", h.pdu_type,
                            h.protocol_family, family));
  }
  switch (static_cast<PduType>(h.pdu_type)) {
    case PduType::kEntityState:
      return DecodeEntityState(in, h);
    case PduType::kPointObjectState:
      return DecodePointObjectState(in, h);
    case PduType::kLinearObjectState:
      return DecodeLinearObjectState(in, h);
  }
  DT_UNREACHABLE();  // every type was checked above
}

PduFrame FrameAt(std::span<const uint8_t> datagram, size_t offset) {
  DT_DEMAND(offset < datagram.size());
  const size_t left = datagram.size() - offset;
  if (left < kHeaderSize) {
    return {{},
            DecodeError{DecodeFailure::kTooShort,
                        fmt::format("{} bytes left at byte {} of a {}-byte datagram, a DIS header "
                                    "needs {}",
                                    left, offset, datagram.size(), kHeaderSize)}};
  }
  // The length field is the header's bytes 8 and 9 (big-endian).
  const size_t length = (static_cast<size_t>(datagram[offset + 8]) << 8) | datagram[offset + 9];
  if (length < kHeaderSize || length > left) {
    return {{},
            DecodeError{DecodeFailure::kLengthMismatch,
                        fmt::format("length field {} at byte {} of a {}-byte datagram ({} bytes "
                                    "left)",
                                    length, offset, datagram.size(), left)}};
  }
  return {datagram.subspan(offset, length), std::nullopt};
}

uint64_t DecodeCounters::rejected_total() const {
  uint64_t sum = 0;
  for (uint64_t n : rejected) sum += n;
  return sum;
}

DecodeResult Decoder::Decode(std::span<const uint8_t> datagram) {
  DecodeResult result = DecodePdu(datagram, exercise_id_);
  if (!result.ok()) {
    ++counters_.rejected[static_cast<size_t>(result.error().failure)];
    return result;
  }
  switch (result.pdu().index()) {
    case 0:
      ++counters_.entity_state;
      break;
    case 1:
      ++counters_.point_object_state;
      break;
    default:
      ++counters_.linear_object_state;
      break;
  }
  return result;
}

}  // namespace dt::dis
