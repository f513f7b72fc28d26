// Exchange: one side of the two-process PDU exchange (send N Updates, receive the peer's N).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "base/feature_id.h"
#include "transport/transport.h"

namespace dt::exchange {

inline constexpr uint8_t kExercise = 1;
inline constexpr double kTerrainM = 10000.0;
inline constexpr NodeAddress kDriver{1, 1};
inline constexpr NodeAddress kPeer{1, 2};

struct Result {
  int64_t sent = 0;
  int64_t received = 0;        // distinct Updates from the peer
  int64_t duplicates = 0;      // Updates from the peer seen again
  uint64_t rejected = 0;       // PDUs dropped by validation
  bool finished = false;       // sent and received everything before the deadline
  std::string ToLine() const;  // "sent=… received=… duplicates=… rejected=… finished=…"
};

// Subscribes, calls ready() (the caller's readiness handshake), then sends `count` valid Update
// PDUs through a PduBus while receiving the peer's. Flow control: MaxFeature PDUs acknowledge
// how many Updates were received, and at most `window` of ours may be unacknowledged, so a burst
// never overruns the receiver. Stops when done or at the deadline.
Result Run(Transport& transport, NodeAddress local, int64_t count,
           std::chrono::steady_clock::time_point deadline, const std::function<void()>& ready,
           int64_t window = 1000);

// For DDS: waits until the peer's readers are matched (volatile data sent earlier is lost).
// A no-op for other transports. Returns false on timeout.
bool AwaitPeerReaders(Transport& transport, int timeout_ms);

}  // namespace dt::exchange
