#include "pdu/pdu_type.h"

#include <fmt/format.h>

namespace dt {

std::string_view PduTypeName(PduType type) {
  switch (type) {
    case PduType::kConstruct:
      return "CONSTRUCT";
    case PduType::kUpdate:
      return "UPDATE";
    case PduType::kDestruct:
      return "DESTRUCT";
    case PduType::kMaxFeature:
      return "MAXFEATURE";
    case PduType::kPlayback:
      return "PLAYBACK";
    case PduType::kAntiEntropy:
      return "ANTIENTROPY";
    case PduType::kVehicleState:
      return "VEHICLESTATE";
    case PduType::kEarthMove:
      return "EARTHMOVE";
    case PduType::kBatch:
      return "BATCH";
  }
  return "UNKNOWN";
}

std::optional<PduType> PduTypeFromRaw(uint8_t raw) {
  for (PduType t : kAllPduTypes) {
    if (static_cast<uint8_t>(t) == raw) return t;
  }
  return std::nullopt;
}

std::string ChannelName(uint8_t exercise_id, PduType type) {
  return fmt::format("DT{}_{}", exercise_id, PduTypeName(type));
}

std::string_view NodeRoleName(NodeRole role) {
  switch (role) {
    case NodeRole::kNode:
      return "node";
    case NodeRole::kServer:
      return "server";
    case NodeRole::kStandby:
      return "standby";
    case NodeRole::kObserver:
      return "observer";
  }
  return "unknown";
}

}  // namespace dt
