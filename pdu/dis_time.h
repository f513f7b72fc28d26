// DIS time stamps: 32 bits, units of 3600 s / 2^31 past the hour, low bit absolute/relative.
#pragma once

#include <chrono>
#include <cstdint>

namespace dt {

// One unit of the DIS time stamp: 3600 s / 2^31, about 1.676 microseconds.
inline constexpr double kDisTimeUnitS = 3600.0 / 2147483648.0;

// Encodes a time past the hour (seconds, [0, 3600); values outside wrap into the hour) with the
// absolute bit (1: clocks synchronised to UTC) or relative bit (0).
uint32_t EncodeDisTimestamp(double seconds_past_hour, bool absolute);

// The seconds past the hour a DIS time stamp names (resolution kDisTimeUnitS).
double DisTimestampSeconds(uint32_t timestamp);
inline bool DisTimestampIsAbsolute(uint32_t timestamp) { return (timestamp & 1u) != 0; }

// Absolute DIS time stamp of a system-clock time (UTC).
uint32_t DisTimestampAt(std::chrono::system_clock::time_point time);
// Absolute DIS time stamp of now.
uint32_t DisTimestampNow();

}  // namespace dt
