// ReplicaThread: one replica with its own LCM transport on its own thread, as each node process
// runs one, so a protocol benchmark measures replicas side by side instead of summing their costs
// on one thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/replica.h"
#include "simulation/bench/lcm_cluster.h"
#include "transport/pdu_bus.h"
#include "transport/transport.h"

namespace dt::bench {

class ReplicaThread {
 public:
  // Step: called on the replica's thread after every dispatch and tick until it returns true.
  using Step = std::function<bool(Replica&)>;

  // Builds the transport (`url`, e.g. udpm://...: its own socket), bus and replica, signs on and
  // starts the loop: wait up to 1 ms for traffic, dispatch it, tick, run the pending steps.
  // Every replica's clock is milliseconds since `epoch_ns` (SteadyNowNs of the caller).
  // With a key the bus authenticates every PDU (pdu/pdu_auth.h).
  // The ground is taken, not copied: a restart in a benchmark costs what a process's does.
  ReplicaThread(const std::string& url, HeightGrid ground, ReplicaConfig config, ChangeStore* store,
                int64_t epoch_ns, std::shared_ptr<const ExerciseKey> key = nullptr,
                bool batch = true);
  // Stops the loop, then destroys replica, bus and transport: a crash, its state is gone.
  ~ReplicaThread();
  ReplicaThread(const ReplicaThread&) = delete;
  ReplicaThread& operator=(const ReplicaThread&) = delete;

  // Queues `step`; the future gives SteadyNowNs() at the moment it returned true. The step's
  // captures must outlive it.
  std::future<int64_t> Post(Step step);
  // Runs `fn` on the replica's thread once and waits for it.
  void Run(const std::function<void(Replica&)>& fn);
  // CPU time the replica's thread has used so far, ns (work done, not time waited for a core).
  int64_t CpuNs();
  // Batches (datagrams of several PDUs) its bus has sent so far, read on its thread.
  uint64_t BatchesSent();

 private:
  struct Pending {
    Step step;
    std::promise<int64_t> done;
  };
  void Loop();
  int64_t NowMs() const { return (SteadyNowNs() - epoch_ns_) / 1000000; }

  int64_t epoch_ns_;
  std::unique_ptr<Transport> transport_;
  std::unique_ptr<PduBus> bus_;
  std::unique_ptr<Replica> replica_;
  int wake_fd_ = -1;  // eventfd: a new step wakes the loop at once
  std::mutex mutex_;
  std::vector<Pending> incoming_;  // guarded by mutex_
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: starts after everything above exists
};

}  // namespace dt::bench
