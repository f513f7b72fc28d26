// SimNetwork: a deterministic in-process network of Transport endpoints with virtual time and
// seeded faults, for simulation tests of many nodes in one process.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <queue>
#include <vector>

#include "transport/fault_model.h"
#include "transport/transport.h"

namespace dt {

// Every endpoint belongs to one node. A message published by one endpoint is offered to every
// endpoint of the same exercise (its own included, unfaulted, as LCM loops back); each copy to
// another node gets its fate from the FaultModel and waits its delay in virtual milliseconds.
// Time moves only through AdvanceMs, and HandleTimeout never blocks: it delivers what is due.
// With the same seed and the same sequence of calls, every run delivers the same messages in
// the same order. Single-threaded; the network must outlive its endpoints.
class SimNetwork {
 public:
  explicit SimNetwork(uint64_t seed, FaultConfig faults = {});
  ~SimNetwork();
  SimNetwork(const SimNetwork&) = delete;
  SimNetwork& operator=(const SimNetwork&) = delete;

  // A new endpoint for `node` in `exercise_id`. Throws std::invalid_argument if the node already
  // has an endpoint in that exercise.
  std::unique_ptr<Transport> Join(NodeAddress node, uint8_t exercise_id);

  FaultModel& faults() { return faults_; }

  // Makes every Publish by `node`'s endpoints fail, as a carrier's write that timed out (a DDS
  // writer held back by a dead reader), until virtual time reaches until_ms: the PDU is not sent
  // and Publish returns an Error. Receiving is unaffected. A later call replaces the window;
  // BlockWrites(node, 0) ends it at once.
  void BlockWrites(NodeAddress node, int64_t until_ms);
  bool WritesBlocked(NodeAddress node) const;

  // Moves virtual time forward; messages whose delay has passed become deliverable.
  void AdvanceMs(int64_t ms);
  int64_t now_ms() const { return now_ms_; }
  // Virtual time of the earliest undelivered message, or -1 if none.
  int64_t NextDeliveryMs() const;
  // Messages published but not yet delivered (including to endpoints that never handle).
  size_t in_flight() const;

  struct Stats {
    uint64_t published = 0;
    uint64_t copies_queued = 0;   // after drops, including duplicates and loopback
    uint64_t dropped = 0;         // deliveries decided lost (drops and partitions)
    uint64_t delivered = 0;       // copies handed to an endpoint's handlers
    uint64_t write_failures = 0;  // Publish calls failed by BlockWrites (not in published)
  };
  const Stats& stats() const { return stats_; }

 private:
  class Endpoint;
  friend class Endpoint;
  struct Pending {
    int64_t due_ms;
    uint64_t order;  // ties delivered in publish order
    PduType type;
    std::shared_ptr<const std::vector<uint8_t>> bytes;
    bool operator>(const Pending& o) const {
      return due_ms != o.due_ms ? due_ms > o.due_ms : order > o.order;
    }
  };
  using Inbox = std::priority_queue<Pending, std::vector<Pending>, std::greater<>>;

  Status Publish(Endpoint& from, PduType type, std::span<const uint8_t> bytes);
  void Leave(Endpoint& endpoint);

  FaultModel faults_;
  int64_t now_ms_ = 0;
  uint64_t next_order_ = 0;
  std::vector<Endpoint*> endpoints_;  // join order: fates are drawn in this order
  std::map<NodeAddress, int64_t> writes_blocked_until_ms_;
  Stats stats_;
};

}  // namespace dt
