// LcmCluster: replicas over a real LCM transport (memq in this process, or udpm), driven in real
// time by one loop, for the protocol benchmarks.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/replica.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"

namespace dt::bench {

// The benchmarks' exercise ID.
inline constexpr uint8_t kBenchExercise = 1;

// Nanoseconds of the steady clock.
int64_t SteadyNowNs();

// Acknowledgements every 10 ms and a window of 4096: at most 409 600 features/s from the
// protocol, so the engine's own cost is what a throughput benchmark measures.
ReplicaConfig FastAckConfig();

// The bus of the member at `address` on `ground`, in the benchmarks' exercise.
PduBusConfig BenchBusConfig(NodeAddress address, const HeightGrid& ground);

// The benchmarks' terrain: 10 km x 10 km, 1001 x 1001 posts at 10 m (render_bench's size).
inline HeightGrid BenchGround() { return HeightGrid(1001, 10.0, 5.0f); }

// Crater n: radius 2 m on a 10 m lattice, distinct for the first 960 400 n, so features do not
// pile up on one spot (the terrain's cost per placed feature grows with the features already
// on its squares).
inline FeatureParams BenchCrater(int64_t n) {
  return FeatureParams::Crater(100 + static_cast<double>(n % 980) * 10.0,
                               100 + static_cast<double>((n / 980) % 980) * 10.0, 2);
}

// `origin`'s change n (1, 2, ...): the Construct of its feature n, BenchCrater(n), at Lamport n.
Change BenchCraterConstruct(NodeAddress origin, int64_t n);

// The bytes of BenchCraterConstruct(origin, 1), as its replica publishes it: every field but the
// vertex edits has a fixed size, so this is the size of every bench crater's.
std::vector<uint8_t> BenchConstructBytes(NodeAddress origin);

// memq:// is one LCM queue per lcm_t, so every member's PduBus sits on an endpoint of one shared
// LcmTransport that hands each message to every live member (as multicast would); a member can
// leave without the others. udpm://... gives each member its own LcmTransport (its own socket).
// Single-threaded: Pump dispatches what arrived and ticks every replica with the wall clock.
class LcmCluster {
 public:
  LcmCluster(std::string url, HeightGrid ground, ReplicaConfig defaults);
  ~LcmCluster();
  LcmCluster(const LcmCluster&) = delete;
  LcmCluster& operator=(const LcmCluster&) = delete;

  // Members started from now on authenticate their PDUs with `key` (null: none, the default).
  void set_key(std::shared_ptr<const ExerciseKey> key) { key_ = std::move(key); }

  // A new replica that signs on at once; `config` overrides the defaults (address, role and
  // store are set here).
  Replica& Start(NodeAddress address, NodeRole role, ChangeStore* store = nullptr);
  Replica& Start(NodeAddress address, NodeRole role, ChangeStore* store, ReplicaConfig config);
  // Destroys the member's replica, bus and transport (a crash: its state is gone).
  void Crash(NodeAddress address);
  Replica& at(NodeAddress address) { return *members_.at(address)->replica; }
  PduBus& bus(NodeAddress address) { return *members_.at(address)->bus; }

  // Waits up to wait_ms for traffic, dispatches everything that arrived to every member, then
  // ticks every replica (address order) at now_ms() if a tick is due.
  void Pump(int wait_ms = 0);
  // 0 (the default): every Pump ticks, so only the engine paces the protocol. node_main ticks at
  // tick_hz (30: every 33 ms) and dispatches in between; a period gives that pacing.
  void set_tick_period_ms(int64_t period_ms) { tick_period_ms_ = period_ms; }
  // Milliseconds of the steady clock since the cluster was made.
  int64_t now_ms() const;

  // memq only: while on, a copy of every Construct message dispatched is kept (the bytes as
  // sent), so a baseline can send exactly the same messages.
  void RecordConstructs(bool on);
  std::vector<std::vector<uint8_t>> TakeRecorded();
  // memq only: wall time spent in the member's handlers (decode, validate, apply) so far, so a
  // run on one thread can say what each replica costs.
  int64_t ReceiveNs(NodeAddress address) const;

 private:
  class MemqHub;
  // Members are destroyed in reverse order: the replica before the bus it subscribed to, the bus
  // before its transport.
  struct Member {
    std::unique_ptr<Transport> transport;  // for memq a MemqHub endpoint
    std::unique_ptr<PduBus> bus;
    std::unique_ptr<Replica> replica;
  };

  std::string url_;
  HeightGrid ground_;
  ReplicaConfig defaults_;
  int64_t start_ns_;
  int64_t tick_period_ms_ = 0;
  int64_t last_tick_ms_ = -1;
  std::shared_ptr<const ExerciseKey> key_;
  std::unique_ptr<MemqHub> hub_;  // memq only
  std::map<NodeAddress, std::unique_ptr<Member>> members_;
};

// Pumps `cluster` until done() or timeout_ms passed; false on timeout.
template <typename Done>
bool PumpUntil(LcmCluster& cluster, int64_t timeout_ms, Done done, int wait_ms = 1) {
  const int64_t deadline = cluster.now_ms() + timeout_ms;
  while (!done()) {
    if (cluster.now_ms() > deadline) return false;
    cluster.Pump(wait_ms);
  }
  return true;
}

}  // namespace dt::bench
