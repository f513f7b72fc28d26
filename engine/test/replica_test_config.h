// The addresses and protocol timing the replica tests share: a server, a standby and two nodes.
#pragma once

#include "engine/replica.h"

namespace dt::testing {

inline constexpr NodeAddress kTestServer{1, 100};
inline constexpr NodeAddress kTestStandby{1, 101};
inline constexpr NodeAddress kTestA{1, 1};
inline constexpr NodeAddress kTestB{1, 2};

// Fast timing for virtual time: reports every 200 ms, silence after 800 ms, a window of 64.
inline ReplicaConfig TestReplicaConfig() {
  ReplicaConfig c;
  c.max_feature_period_ms = 200;
  c.silence_ms = 800;
  c.playback_retry_ms = 300;
  c.playback_window = 64;
  return c;
}

}  // namespace dt::testing
