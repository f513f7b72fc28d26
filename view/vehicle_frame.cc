#include "view/vehicle_frame.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>

#include <fmt/format.h>

namespace dt {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the binary vehicle message is written in the host's order, little-endian");

template <typename T>
void Put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}
template <typename T>
T Get(const std::string& in, size_t at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  return v;
}

int16_t Clamp16(double v) {
  return static_cast<int16_t>(std::lround(std::fmax(-32767.0, std::fmin(32767.0, v))));
}

}  // namespace

std::string VehicleFrameHeader(uint64_t seq, int64_t t_ms, uint32_t count) {
  std::string out;
  out.reserve(kVehicleFrameHeaderBytes + kVehicleRecordBytes * count);
  out.append("DTV1", 4);
  Put(out, static_cast<uint32_t>(seq));
  Put(out, static_cast<double>(t_ms));
  Put(out, count);
  Put(out, uint32_t{0});
  return out;
}

void AppendVehicleRecord(std::string& frame, uint32_t slot, const VehicleView& v) {
  DT_DEMAND(slot < kVehicleDeadBit);
  Put(frame, slot | (v.alive ? 0u : kVehicleDeadBit));
  Put(frame, static_cast<float>(v.x_m));
  Put(frame, static_cast<float>(v.z_m));
  // The heading into (-pi, pi], so that 1/10 000 radian fits 16 bits.
  const double h = std::remainder(v.heading_rad, 2 * std::numbers::pi);
  Put(frame, Clamp16(h * 10000.0));
  Put(frame, Clamp16(v.speed_mps * 100.0));
}

Result<DecodedVehicleFrame> DecodeVehicleFrame(const std::string& frame) {
  if (frame.size() < kVehicleFrameHeaderBytes || frame.compare(0, 4, "DTV1") != 0) {
    return Error{fmt::format("vehicle frame: {} bytes without the \"DTV1\" header", frame.size())};
  }
  DecodedVehicleFrame out;
  out.seq = Get<uint32_t>(frame, 4);
  out.t_ms = static_cast<int64_t>(Get<double>(frame, 8));
  const uint32_t count = Get<uint32_t>(frame, 16);
  if (frame.size() != kVehicleFrameHeaderBytes + kVehicleRecordBytes * count) {
    return Error{fmt::format("vehicle frame: {} records need {} bytes, not {}", count,
                             kVehicleFrameHeaderBytes + kVehicleRecordBytes * count, frame.size())};
  }
  for (uint32_t i = 0; i < count; ++i) {
    const size_t at = kVehicleFrameHeaderBytes + kVehicleRecordBytes * i;
    const uint32_t slot = Get<uint32_t>(frame, at);
    out.records.push_back({slot & ~kVehicleDeadBit, Get<float>(frame, at + 4),
                           Get<float>(frame, at + 8), Get<int16_t>(frame, at + 12) / 10000.0,
                           Get<int16_t>(frame, at + 14) / 100.0, (slot & kVehicleDeadBit) == 0});
  }
  return out;
}

}  // namespace dt
