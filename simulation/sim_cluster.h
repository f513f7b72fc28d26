// SimCluster: replicas over one SimNetwork in virtual time, crashed and restarted at will.
#pragma once

#include <cstdint>
#include <map>
#include <memory>

#include "engine/replica.h"
#include "simulation/sim_network.h"
#include "transport/pdu_bus.h"

namespace dt::testing {

// Each member owns its transport, bus and replica; a crash destroys all three (the replica's
// state is lost; a store given by the caller survives, as a database file would).
class SimCluster {
 public:
  SimCluster(uint64_t seed, HeightGrid ground, ReplicaConfig defaults, FaultConfig faults = {});
  ~SimCluster();

  // A new replica for `address` that signs on at once. `store` (servers) and `ids` (nodes) are the
  // caller's and survive a crash, as files would.
  // `ground`: another ground than the cluster's for this replica (a member started on the wrong
  // file); null: the cluster's.
  Replica& Start(NodeAddress address, NodeRole role, ChangeStore* store = nullptr,
                 IdReservation* ids = nullptr, const BaseGround* ground = nullptr);
  void Crash(NodeAddress address);
  bool alive(NodeAddress address) const { return members_.count(address) != 0; }
  Replica& at(NodeAddress address) { return *members_.at(address)->replica; }

  // Moves virtual time by `ms` in steps of step_ms: each step delivers what is due and ticks
  // every replica (in address order).
  void Run(int64_t ms, int64_t step_ms = 10);
  // Moves virtual time the same way but only delivers: no replica ticks, so only what the
  // replicas do inside their handlers happens.
  void Deliver(int64_t ms, int64_t step_ms = 10);
  int64_t now_ms() const { return net_.now_ms(); }
  SimNetwork& net() { return net_; }
  std::vector<NodeAddress> live() const;

 private:
  // Members are destroyed in reverse order: the replica before the bus it subscribed to, the bus
  // before its transport.
  struct Member {
    std::unique_ptr<Transport> transport;
    std::unique_ptr<PduBus> bus;
    std::unique_ptr<Replica> replica;
  };

  SimNetwork net_;
  HeightGrid ground_;
  ReplicaConfig defaults_;
  std::map<NodeAddress, std::unique_ptr<Member>> members_;
};

}  // namespace dt::testing
