#include "pdu/vehicle_state.h"

#include <algorithm>

#include <fmt/format.h>

namespace dt {
namespace {

struct KnownType {
  std::string_view name;
  EntityType type;
};
// Platform (1), land (1), USA (225). The tank is SISO-REF-010's M1A2 (category 1 tank,
// subcategory 1 M1 Abrams, specific 3); the truck, the jeep and the bulldozer are named by
// category alone (7 large wheeled utility vehicle, 6 small wheeled utility vehicle, 18 engineer
// equipment; subcategory 0). Without a type a vehicle is not shared: a bulldozer's blade work
// reached every node while the bulldozer itself stayed unseen.
constexpr std::array<KnownType, 4> kKnownTypes = {{
    {"tank", {1, 1, 225, 1, 1, 3, 0}},
    {"truck", {1, 1, 225, 7, 0, 0, 0}},
    {"jeep", {1, 1, 225, 6, 0, 0, 0}},
    {"bulldozer", {1, 1, 225, 18, 0, 0, 0}},
}};

}  // namespace

std::string EntityId::ToString() const {
  return fmt::format("{}:{}:{}", site, application, entity);
}

std::string EntityType::ToString() const {
  return fmt::format("{}.{}.{}.{}.{}.{}.{}", kind, domain, country, category, subcategory, specific,
                     extra);
}

std::optional<EntityType> EntityTypeOfVehicle(std::string_view type_name) {
  for (const auto& k : kKnownTypes) {
    if (k.name == type_name) return k.type;
  }
  return std::nullopt;
}

std::string_view VehicleNameOfEntityType(const EntityType& type) {
  for (const auto& k : kKnownTypes) {
    if (k.type == type) return k.name;
  }
  return {};
}

std::string_view DeadReckoningAlgorithmName(DeadReckoningAlgorithm a) {
  switch (a) {
    case DeadReckoningAlgorithm::kStatic:
      return "static";
    case DeadReckoningAlgorithm::kFpw:
      return "fpw";
    case DeadReckoningAlgorithm::kRpw:
      return "rpw";
    case DeadReckoningAlgorithm::kRvw:
      return "rvw";
    case DeadReckoningAlgorithm::kFvw:
      return "fvw";
  }
  return "unknown";
}

std::optional<DeadReckoningAlgorithm> ParseDeadReckoningAlgorithm(std::string_view name) {
  for (uint8_t raw = 1; raw <= 5; ++raw) {
    const auto a = static_cast<DeadReckoningAlgorithm>(raw);
    if (DeadReckoningAlgorithmName(a) == name) return a;
  }
  return std::nullopt;
}

dtpdu::vehicle_state_t ToVehicleState(const VehicleStateFields& s) {
  dtpdu::vehicle_state_t pdu{};
  pdu.entity_id.site = static_cast<int16_t>(s.id.site);
  pdu.entity_id.application = static_cast<int16_t>(s.id.application);
  pdu.entity_id.entity = s.id.entity;
  pdu.force_id = s.force_id;
  pdu.entity_type.kind = s.type.kind;
  pdu.entity_type.domain = s.type.domain;
  pdu.entity_type.country = static_cast<int16_t>(s.type.country);
  pdu.entity_type.category = s.type.category;
  pdu.entity_type.subcategory = s.type.subcategory;
  pdu.entity_type.specific = s.type.specific;
  pdu.entity_type.extra = s.type.extra;
  for (int i = 0; i < 3; ++i) {
    pdu.location_m[i] = s.location_m[static_cast<size_t>(i)];
    pdu.linear_velocity_mps[i] = s.velocity_mps[static_cast<size_t>(i)];
    pdu.linear_acceleration_mps2[i] = s.acceleration_mps2[static_cast<size_t>(i)];
    pdu.angular_velocity_rad_s[i] = s.angular_velocity_body_rad_s[static_cast<size_t>(i)];
  }
  pdu.orientation_rad[0] = s.heading_rad;
  pdu.orientation_rad[1] = s.pitch_rad;
  pdu.orientation_rad[2] = s.roll_rad;
  pdu.appearance = static_cast<int32_t>(s.appearance);
  pdu.dead_reckoning_algorithm = static_cast<uint8_t>(s.algorithm);
  pdu.marking_charset = kMarkingAscii;
  for (size_t i = 0; i < kMarkingChars; ++i) {
    pdu.marking[i] = i < s.marking.size() ? static_cast<uint8_t>(s.marking[i]) : 0;
  }
  return pdu;
}

VehicleStateFields FromVehicleState(const dtpdu::vehicle_state_t& pdu) {
  VehicleStateFields s;
  s.id = {static_cast<uint16_t>(pdu.entity_id.site),
          static_cast<uint16_t>(pdu.entity_id.application),
          static_cast<uint16_t>(pdu.entity_id.entity)};
  s.force_id = pdu.force_id;
  s.type = {pdu.entity_type.kind,
            pdu.entity_type.domain,
            static_cast<uint16_t>(pdu.entity_type.country),
            pdu.entity_type.category,
            pdu.entity_type.subcategory,
            pdu.entity_type.specific,
            pdu.entity_type.extra};
  for (size_t i = 0; i < 3; ++i) {
    s.location_m[i] = pdu.location_m[i];
    s.velocity_mps[i] = pdu.linear_velocity_mps[i];
    s.acceleration_mps2[i] = pdu.linear_acceleration_mps2[i];
    s.angular_velocity_body_rad_s[i] = pdu.angular_velocity_rad_s[i];
  }
  s.heading_rad = pdu.orientation_rad[0];
  s.pitch_rad = pdu.orientation_rad[1];
  s.roll_rad = pdu.orientation_rad[2];
  s.appearance = static_cast<uint32_t>(pdu.appearance);
  s.algorithm = static_cast<DeadReckoningAlgorithm>(pdu.dead_reckoning_algorithm);
  for (size_t i = 0; i < kMarkingChars && pdu.marking[i] != 0; ++i) {
    s.marking.push_back(static_cast<char>(pdu.marking[i]));
  }
  return s;
}

}  // namespace dt
