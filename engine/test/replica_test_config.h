// The addresses and protocol timing the replica tests share: a server, a standby and two nodes.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/id_reservation.h"
#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "simulation/sim_cluster.h"
#include "terrain/terrain_digest.h"
#include "transport/pdu_bus.h"
#include "transport/transport.h"

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

// The ground the replica tests share: 33 x 33 posts 4 m apart, relief 10 m.
inline HeightGrid TestGround() { return HeightGrid(33, 4.0, 10.0f); }

// A forged MaxFeature names the test ground, as every member's does (docs/pdu.md "Ground
// identity"); one naming another ground is refused.
inline void StampTestGround(dtpdu::max_feature_t& m) {
  const TerrainDigest d = ComputeDigest(TestGround());
  m.ground_digest[0] = static_cast<int64_t>(d.high);
  m.ground_digest[1] = static_cast<int64_t>(d.low);
}

// A server and nodes A and B on one SimCluster, started and given 1 s of virtual time to sign
// on; the base of the replica test fixtures. `ids_a`: A's feature number reservation, if any.
class ServerAndTwoNodes {
 public:
  ServerAndTwoNodes(uint64_t seed, const ReplicaConfig& config, IdReservation* ids_a = nullptr)
      : cluster_(seed, TestGround(), config) {
    cluster_.Start(kTestServer, NodeRole::kServer, &store_);
    cluster_.Start(kTestA, NodeRole::kNode, nullptr, ids_a);
    cluster_.Start(kTestB, NodeRole::kNode);
    cluster_.Run(1000);
  }
  Replica& A() { return cluster_.at(kTestA); }
  Replica& B() { return cluster_.at(kTestB); }
  Replica& S() { return cluster_.at(kTestServer); }

 protected:
  // A bus of the test's own that sends as `who` on the cluster's network (a member with no
  // replica, or forged PDUs); the fixture keeps it.
  PduBus& BusAs(NodeAddress who) {
    transports_.push_back(cluster_.net().Join(who, 1));
    PduBusConfig bc;
    bc.exercise_id = 1;
    bc.local = who;
    bc.terrain_size_x_m = bc.terrain_size_z_m = 128.0;
    bc.clock = [] { return 0u; };
    buses_.push_back(std::make_unique<PduBus>(*transports_.back(), bc));
    return *buses_.back();
  }

  MemoryChangeStore store_;
  SimCluster cluster_;
  std::vector<std::unique_ptr<Transport>> transports_;
  std::vector<std::unique_ptr<PduBus>> buses_;
};

}  // namespace dt::testing
