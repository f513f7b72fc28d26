// Golden DIS PDUs: structs and the bytes docs/dis.md's layouts give for them, shared by tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dis/dis_pdu.h"

namespace dt::dis::testing {

// Bytes from a hex string; spaces are ignored.
inline std::vector<uint8_t> FromHex(const std::string& hex) {
  std::vector<uint8_t> out;
  std::string digits;
  for (char c : hex) {
    if (c != ' ' && c != '\n') digits.push_back(c);
  }
  for (size_t i = 0; i + 1 < digits.size(); i += 2) {
    out.push_back(static_cast<uint8_t>(std::stoi(digits.substr(i, 2), nullptr, 16)));
  }
  return out;
}

// Values with short exact float forms, so each byte below can be checked by eye.
inline EntityStatePdu GoldenEntityState() {
  EntityStatePdu p;
  p.header.exercise_id = 5;
  p.header.timestamp = 0x12345679;
  p.entity_id = {0x0102, 0x0304, 0x0506};
  p.force_id = 1;
  p.entity_type = {1, 1, 225, 1, 2, 3, 4};
  p.alternative_entity_type = {1, 1, 225, 1, 2, 3, 5};
  p.linear_velocity = {1.5f, -0.25f, 2.0f};
  p.location = {1.0, -2.5, 4096.0};
  p.orientation = {0.5f, -1.0f, 0.25f};
  p.appearance = 0x00800001;
  p.dead_reckoning.algorithm = 4;
  p.dead_reckoning.linear_acceleration = {0.125f, 8.0f, -4.0f};
  p.dead_reckoning.angular_velocity = {0.75f, 3.0f, -0.5f};
  p.marking.character_set = 1;
  p.marking.characters = {'D', 'T', '-', '1'};
  p.capabilities = 2;
  return p;
}

inline const char* kGoldenEntityStateHex =
    "07 05 01 01 12345679 0090 00 00"  // header
    "0102 0304 0506 01 00"             // entity ID, force, no variable parameters
    "01 01 00E1 01 02 03 04"           // entity type
    "01 01 00E1 01 02 03 05"           // alternative entity type
    "3FC00000 BE800000 40000000"       // linear velocity
    "3FF0000000000000 C004000000000000 40B0000000000000"  // location
    "3F000000 BF800000 3E800000"                          // orientation
    "00800001"                                            // appearance
    "04 000000000000000000000000000000"  // dead reckoning: algorithm, other parameters
    "3E000000 41000000 C0800000"         // linear acceleration
    "3F400000 40400000 BF000000"         // angular velocity
    "01 44542D31 00000000000000"         // marking "DT-1"
    "00000002";                          // capabilities

inline PointObjectStatePdu GoldenPointObjectState() {
  PointObjectStatePdu p;
  p.header.exercise_id = 5;
  p.object_id = {1, 2, 3};
  p.update_number = 7;
  p.modifications = 3;
  p.object_type = {1, 1, 3, 0};
  p.location = {1.0, -2.5, 4096.0};
  p.orientation = {0.5f, -1.0f, 0.25f};
  p.specific_appearance = 0x00961E14;  // crater: diameter 20 m, depth 30 cm, height 150 cm
  p.general_appearance = 100;
  p.requester_id = {1, 2};
  p.receiving_id = {0xFFFF, 0xFFFF};
  return p;
}

inline const char* kGoldenPointObjectStateHex =
    "07 05 2B 09 00000000 0058 00 00"  // header
    "0001 0002 0003"                   // object ID
    "0000 0000 0000"                   // referenced object ID
    "0007 00 03"                       // update number, force, modifications
    "01 01 03 00"                      // object type: domain, kind, category, subcategory
    "3FF0000000000000 C004000000000000 40B0000000000000"  // location
    "3F000000 BF800000 3E800000"                          // orientation
    "00961E14 0064 0000"   // specific appearance, general appearance, padding
    "0001 0002 FFFF FFFF"  // requester, receiving
    "00000000";            // padding

inline LinearObjectStatePdu GoldenLinearObjectState() {
  LinearObjectStatePdu p;
  p.header.exercise_id = 5;
  p.object_id = {1, 2, 4};
  p.update_number = 1;
  p.requester_id = {1, 2};
  p.receiving_id = {0xFFFF, 0xFFFF};
  p.object_type = {1, 1, 0, 0};
  LinearSegment s;
  s.segment_number = 1;
  s.general_appearance = 100;
  s.location = {1.0, -2.5, 4096.0};
  s.orientation = {0.5f, -1.0f, 0.25f};
  s.length_m = 50.0f;
  s.width_m = 6.0f;
  s.height_m = 2.0f;
  s.depth_m = 0.0f;
  p.segments.push_back(s);
  return p;
}

inline const char* kGoldenLinearObjectStateHex =
    "07 05 2C 09 00000000 0068 00 00"  // header
    "0001 0002 0004"                   // object ID
    "0000 0000 0000"                   // referenced object ID
    "0001 00 01"                       // update number, force, number of segments
    "0001 0002 FFFF FFFF"              // requester, receiving
    "01 01 00 00"                      // object type
    "01 00 0064 00000000"              // segment: number, modifications, general, specific
    "3FF0000000000000 C004000000000000 40B0000000000000"  // segment location
    "3F000000 BF800000 3E800000"                          // segment orientation
    "42480000 40C00000 40000000 00000000"                 // length, width, height, depth
    "00000000";                                           // padding

}  // namespace dt::dis::testing
