// The DIS 7 (IEEE 1278.1-2012) records and PDUs dynterrain exchanges: header, Entity State,
// Point Object State and Linear Object State. Field-by-field layouts: docs/dis.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dt::dis {

inline constexpr uint8_t kProtocolVersionDis7 = 7;
inline constexpr uint8_t kProtocolVersionDis6 = 6;  // accepted on input for Entity State only

// PDU types (SISO-REF-010 "DIS PDU Type").
enum class PduType : uint8_t {
  kEntityState = 1,
  kPointObjectState = 43,
  kLinearObjectState = 44,
};

// Protocol families (SISO-REF-010 "Protocol Family").
inline constexpr uint8_t kFamilyEntityInformation = 1;
inline constexpr uint8_t kFamilySyntheticEnvironment = 9;

inline constexpr size_t kHeaderSize = 12;
inline constexpr size_t kEntityStateSize = 144;  // without variable parameters
inline constexpr size_t kVariableParameterSize = 16;
inline constexpr size_t kPointObjectStateSize = 88;
inline constexpr size_t kLinearObjectStateSize = 40;  // without segments
inline constexpr size_t kLinearSegmentSize = 64;
// A DIS PDU's length field is 16 bits; a datagram larger than this cannot be one PDU.
inline constexpr size_t kMaxPduSize = 65535;

// PDU header record (6.2.66), 12 bytes.
struct Header {
  uint8_t protocol_version = kProtocolVersionDis7;
  uint8_t exercise_id = 1;
  uint8_t pdu_type = 0;
  uint8_t protocol_family = 0;
  uint32_t timestamp = 0;  // DIS time stamp (pdu/dis_time.h)
  uint16_t length = 0;     // whole PDU in bytes; the encoder fills it in
  uint8_t pdu_status = 0;
  bool operator==(const Header&) const = default;
};

// Simulation Address record (6.2.79): site and application.
struct SimulationAddress {
  uint16_t site = 0;
  uint16_t application = 0;
  bool operator==(const SimulationAddress&) const = default;
};

// Entity Identifier / Object Identifier record (6.2.28): site, application, number.
struct EntityId {
  uint16_t site = 0;
  uint16_t application = 0;
  uint16_t entity = 0;
  bool operator==(const EntityId&) const = default;
};

// Entity Type record (6.2.30), 8 bytes.
struct EntityType {
  uint8_t kind = 0;
  uint8_t domain = 0;
  uint16_t country = 0;
  uint8_t category = 0;
  uint8_t subcategory = 0;
  uint8_t specific = 0;
  uint8_t extra = 0;
  bool operator==(const EntityType&) const = default;
};

// Object Type record (6.2.64), 4 bytes: domain first, then kind.
struct ObjectType {
  uint8_t domain = 0;
  uint8_t kind = 0;
  uint8_t category = 0;
  uint8_t subcategory = 0;
  bool operator==(const ObjectType&) const = default;
};

// 32-bit floating-point three-vector (velocities, accelerations, angular velocities).
struct Vector3F {
  float x = 0, y = 0, z = 0;
  bool operator==(const Vector3F&) const = default;
};

// World Coordinates record (6.2.98): WGS-84 geocentric metres.
struct WorldCoordinates {
  double x = 0, y = 0, z = 0;
  bool operator==(const WorldCoordinates&) const = default;
};

// Euler Angles record (6.2.33): radians, psi about Z, theta about Y, phi about X.
struct EulerAngles {
  float psi = 0, theta = 0, phi = 0;
  bool operator==(const EulerAngles&) const = default;
};

// Dead reckoning algorithms (SISO-REF-010 "Dead Reckoning Algorithm").
enum class DeadReckoningAlgorithm : uint8_t {
  kOther = 0,
  kStatic = 1,
  kFpw = 2,  // fixed orientation, constant velocity, world coordinates
  kRpw = 3,  // rotating, constant velocity, world
  kRvw = 4,  // rotating, varying velocity, world
  kFvw = 5,  // fixed, varying velocity, world
  kFpb = 6,
  kRpb = 7,
  kRvb = 8,
  kFvb = 9,
};
inline constexpr uint8_t kMaxDeadReckoningAlgorithm = 9;

// Dead Reckoning Parameters record (6.2.19), 40 bytes.
struct DeadReckoning {
  uint8_t algorithm = static_cast<uint8_t>(DeadReckoningAlgorithm::kStatic);
  std::array<uint8_t, 15> other_parameters{};
  Vector3F linear_acceleration;  // world coordinates, m/s^2
  Vector3F angular_velocity;     // body coordinates, rad/s
  bool operator==(const DeadReckoning&) const = default;
};

inline constexpr uint8_t kMarkingAscii = 1;
inline constexpr size_t kMarkingChars = 11;

// Entity Marking record (6.2.29): character set and 11 characters, zero-padded.
struct Marking {
  uint8_t character_set = kMarkingAscii;
  std::array<char, kMarkingChars> characters{};
  bool operator==(const Marking&) const = default;
};

// One Variable Parameter record (6.2.94): a record type and 15 bytes, kept as they came.
struct VariableParameter {
  uint8_t record_type = 0;
  std::array<uint8_t, 15> data{};
  bool operator==(const VariableParameter&) const = default;
};

// Entity State PDU (7.2.2), type 1.
struct EntityStatePdu {
  Header header;
  EntityId entity_id;
  uint8_t force_id = 0;
  EntityType entity_type;
  EntityType alternative_entity_type;
  Vector3F linear_velocity;  // world coordinates, m/s
  WorldCoordinates location;
  EulerAngles orientation;
  uint32_t appearance = 0;
  DeadReckoning dead_reckoning;
  Marking marking;
  uint32_t capabilities = 0;
  std::vector<VariableParameter> variable_parameters;  // at most 255
  bool operator==(const EntityStatePdu&) const = default;
};

// General Object Appearance (SISO-REF-010 "Object State Appearance General"), 16 bits.
namespace general_appearance {
inline constexpr uint16_t kPercentCompleteMask = 0x00FF;  // bits 0-7
inline constexpr int kDamageShift = 8;                    // bits 8-9
inline constexpr uint16_t kDamageMask = 0x0300;
inline constexpr uint16_t kDamageNone = 0;
inline constexpr uint16_t kDamageDamaged = 1;
inline constexpr uint16_t kDamageDestroyed = 2;
inline constexpr uint16_t kPredistributed = 1u << 10;
inline constexpr uint16_t kDeactivated = 1u << 11;  // bit 11: state, 1 = deactivated
inline constexpr uint16_t kSmoking = 1u << 12;
inline constexpr uint16_t kFlaming = 1u << 13;
}  // namespace general_appearance

// Object State Modification record bits (Point and Linear objects).
inline constexpr uint8_t kModifiedLocation = 1u << 0;
inline constexpr uint8_t kModifiedOrientation = 1u << 1;

// Point Object State PDU (7.10.4), type 43, 88 bytes.
struct PointObjectStatePdu {
  Header header;
  EntityId object_id;
  EntityId referenced_object_id;
  uint16_t update_number = 0;
  uint8_t force_id = 0;
  uint8_t modifications = 0;
  ObjectType object_type;
  WorldCoordinates location;
  EulerAngles orientation;
  uint32_t specific_appearance = 0;  // object-type specific (crater: docs/dis.md)
  uint16_t general_appearance = 0;
  SimulationAddress requester_id;
  SimulationAddress receiving_id;
  bool operator==(const PointObjectStatePdu&) const = default;
};

// Linear Segment Parameter record (6.2.52), 64 bytes.
struct LinearSegment {
  uint8_t segment_number = 1;
  uint8_t modifications = 0;
  uint16_t general_appearance = 0;
  uint32_t specific_appearance = 0;
  WorldCoordinates location;  // the segment's origin
  EulerAngles orientation;    // segment x axis = its length
  float length_m = 0;         // along +x from the location
  float width_m = 0;          // half to either side (+y and -y)
  float height_m = 0;         // above ground
  float depth_m = 0;          // below ground
  bool operator==(const LinearSegment&) const = default;
};

// Linear Object State PDU (7.10.5), type 44, 40 bytes + 64 per segment.
struct LinearObjectStatePdu {
  Header header;
  EntityId object_id;
  EntityId referenced_object_id;
  uint16_t update_number = 0;
  uint8_t force_id = 0;
  SimulationAddress requester_id;
  SimulationAddress receiving_id;
  ObjectType object_type;
  std::vector<LinearSegment> segments;  // at most 255
  bool operator==(const LinearObjectStatePdu&) const = default;
};

}  // namespace dt::dis
