// VehicleFrame: the binary WebSocket message that carries the vehicles' moves to the page
// (docs/view.md "The binary vehicle message"), and its reading back for tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/result.h"
#include "view/vehicle_source.h"

namespace dt {

// Little-endian throughout. A 24-byte header, "DTV1", the delta's seq (low 32 bits), its t_ms
// (a double, epoch ms) and the record count, then per vehicle 16 bytes: its slot (bit 31 set when
// dead), x and z as floats (metres), the heading in 1/10 000 radian and the speed in cm/s as
// int16. Fixed-size records let the page read them through typed arrays, with no text to parse
// and no object per vehicle.
inline constexpr size_t kVehicleFrameHeaderBytes = 24;
inline constexpr size_t kVehicleRecordBytes = 16;
inline constexpr uint32_t kVehicleDeadBit = 0x80000000u;

// A header for `count` records.
std::string VehicleFrameHeader(uint64_t seq, int64_t t_ms, uint32_t count);
// One vehicle's record. `slot` (below 2^31) is what the page knows the vehicle by: the snapshot
// and the JSON deltas carry it with the vehicle's ID, owner and type.
void AppendVehicleRecord(std::string& frame, uint32_t slot, const VehicleView& v);

struct VehicleRecord {
  uint32_t slot = 0;
  double x_m = 0, z_m = 0, heading_rad = 0, speed_mps = 0;
  bool alive = true;
};
struct DecodedVehicleFrame {
  uint32_t seq = 0;
  int64_t t_ms = 0;
  std::vector<VehicleRecord> records;
};
// Reads a frame back; an error names what is wrong (magic, size).
Result<DecodedVehicleFrame> DecodeVehicleFrame(const std::string& frame);

}  // namespace dt
