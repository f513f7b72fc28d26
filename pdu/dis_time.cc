#include "pdu/dis_time.h"

#include <cmath>

namespace dt {

uint32_t EncodeDisTimestamp(double seconds_past_hour, bool absolute) {
  double s = seconds_past_hour;
  // Within the hour already (every time stamp of now): fmod would give s itself, exactly.
  if (!(s >= 0.0 && s < 3600.0)) {
    s = std::fmod(s, 3600.0);
    if (!(s >= 0.0)) s = std::isfinite(s) ? s + 3600.0 : 0.0;
  }
  // 31 bits of units; the last unit of the hour saturates rather than wrapping to 0.
  auto units = static_cast<uint64_t>(std::floor(s / kDisTimeUnitS));
  if (units > 0x7FFFFFFFull) units = 0x7FFFFFFFull;
  return static_cast<uint32_t>(units << 1) | (absolute ? 1u : 0u);
}

double DisTimestampSeconds(uint32_t timestamp) {
  return static_cast<double>(timestamp >> 1) * kDisTimeUnitS;
}

uint32_t DisTimestampAt(std::chrono::system_clock::time_point time) {
  using namespace std::chrono;
  const auto since_epoch_us = duration_cast<microseconds>(time.time_since_epoch()).count();
  const int64_t hour_us = int64_t{3600} * 1000000;
  int64_t past_hour_us = since_epoch_us % hour_us;
  if (past_hour_us < 0) past_hour_us += hour_us;
  return EncodeDisTimestamp(static_cast<double>(past_hour_us) / 1e6, true);
}

uint32_t DisTimestampNow() { return DisTimestampAt(std::chrono::system_clock::now()); }

}  // namespace dt
