// VehicleState PDU vocabulary: entity IDs, SISO-REF-010 entity types, appearance bits, and the
// conversion between a vehicle's state and its PDU (docs/pdu.md "VehicleState").
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "base/feature_id.h"
#include "dtpdu/vehicle_state_t.hpp"

namespace dt {

// A DIS entity ID. A node names its vehicles (its site, its host, 1, 2, ...).
struct EntityId {
  uint16_t site = 0;
  uint16_t application = 0;
  uint16_t entity = 0;  // 1 .. 65535
  auto operator<=>(const EntityId&) const = default;
  std::string ToString() const;  // "site:application:entity"
};

// A DIS entity type record.
struct EntityType {
  uint8_t kind = 0, domain = 0;
  uint16_t country = 0;
  uint8_t category = 0, subcategory = 0, specific = 0, extra = 0;
  auto operator<=>(const EntityType&) const = default;
  std::string ToString() const;  // "1.1.225.1.1.3.0"
};

// SISO-REF-010 types of the built-in vehicle types (docs/pdu.md "Entity types"): "tank",
// "truck", "jeep", "bulldozer". nullopt for another name.
std::optional<EntityType> EntityTypeOfVehicle(std::string_view type_name);
// The built-in vehicle type name of an entity type; empty for a type no built-in has.
std::string_view VehicleNameOfEntityType(const EntityType& type);

// DIS force IDs this exercise uses.
inline constexpr uint8_t kMaxForceId = 3;  // 0 other, 1 friendly, 2 opposing, 3 neutral

// Dead-reckoning algorithms (DIS DRM values, world coordinates).
enum class DeadReckoningAlgorithm : uint8_t {
  kStatic = 1,  // DRM 1: no motion
  kFpw = 2,     // DRM 2: fixed orientation, constant velocity
  kRpw = 3,     // DRM 3: rotating, constant velocity
  kRvw = 4,     // DRM 4: rotating, constant acceleration
  kFvw = 5,     // DRM 5: fixed orientation, constant acceleration
};
inline bool IsValidDeadReckoningAlgorithm(uint8_t raw) { return raw >= 1 && raw <= 5; }
// "static", "fpw", "rpw", "rvw", "fvw".
std::string_view DeadReckoningAlgorithmName(DeadReckoningAlgorithm a);
std::optional<DeadReckoningAlgorithm> ParseDeadReckoningAlgorithm(std::string_view name);

// Appearance bits. Damage (bits 3-4) and mobility kill (bit 1) and the state bit (23,
// deactivated) are the DIS land-platform bits; on-bridge and falling are this exercise's, in
// bits 28 and 29 (a gateway to outside DIS peers must clear them).
namespace appearance {
inline constexpr uint32_t kMobilityKill = 1u << 1;
inline constexpr uint32_t kDamageShift = 3;
inline constexpr uint32_t kDamageMask = 3u << kDamageShift;  // 0 none .. 3 destroyed
inline constexpr uint32_t kDestroyed = 3u << kDamageShift;
inline constexpr uint32_t kDeactivated = 1u << 23;  // the vehicle has left the exercise
inline constexpr uint32_t kOnBridge = 1u << 28;
inline constexpr uint32_t kFalling = 1u << 29;
inline constexpr uint32_t kKnown =
    kMobilityKill | kDamageMask | kDeactivated | kOnBridge | kFalling;
}  // namespace appearance

// Marking: DIS's 11 characters of character set 1 (ASCII).
inline constexpr uint8_t kMarkingAscii = 1;
inline constexpr size_t kMarkingChars = 11;

// One vehicle's state as the PDU carries it (world frame, docs/conventions.md).
struct VehicleStateFields {
  EntityId id;
  uint8_t force_id = 1;
  EntityType type;
  std::array<double, 3> location_m{};
  std::array<double, 3> velocity_mps{};
  double heading_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;
  uint32_t appearance = 0;
  DeadReckoningAlgorithm algorithm = DeadReckoningAlgorithm::kRvw;
  std::array<double, 3> acceleration_mps2{};
  std::array<double, 3> angular_velocity_body_rad_s{};  // (ahead, up, left)
  std::string marking;  // at most 11 printable ASCII characters; longer is cut
  bool operator==(const VehicleStateFields&) const = default;
};

// Fills the vehicle fields; header, sender and sender_seq are PduBus's to set.
dtpdu::vehicle_state_t ToVehicleState(const VehicleStateFields& state);
// The inverse, for a validated PDU (values are copied as they are).
VehicleStateFields FromVehicleState(const dtpdu::vehicle_state_t& pdu);

}  // namespace dt

template <>
struct std::hash<dt::EntityId> {
  size_t operator()(const dt::EntityId& e) const noexcept {
    return std::hash<uint64_t>{}((uint64_t{e.site} << 32) | (uint64_t{e.application} << 16) |
                                 e.entity);
  }
};
