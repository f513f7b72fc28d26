// FaultyTransport: wraps any Transport and injects seeded drops, duplicates, delays, reordering
// and partitions into what it receives.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <queue>
#include <vector>

#include "transport/fault_model.h"
#include "transport/transport.h"

namespace dt {

// What FaultConfig's delay ticks count in a FaultyTransport.
enum class DelayUnit { kHandleCalls, kMilliseconds };

// Faults apply to received messages, per receiver: the sender is read from the PDU bytes
// (PeekSender), so partitions work over real carriers too. Delays count HandleTimeout calls, or
// milliseconds of the steady clock; a message with delay 0 is delivered in the call that
// received it. While messages are held, HandleTimeout waits on the inner transport no longer
// than until the next release (not at all when counting calls); an event loop should call
// HandleTimeout when held() > 0 even if the fd is quiet. Decisions are deterministic for a given
// seed and arrival order (the arrival order of a real network is not).
class FaultyTransport final : public Transport {
 public:
  FaultyTransport(std::unique_ptr<Transport> inner, NodeAddress local, FaultConfig faults,
                  uint64_t seed, DelayUnit unit = DelayUnit::kHandleCalls);

  Status Publish(PduType type, std::span<const uint8_t> bytes) override;
  void Subscribe(PduType type, Handler handler) override;
  Result<int> HandleTimeout(int timeout_ms) override;
  int Fd() const override { return inner_->Fd(); }
  std::string Url() const override { return "faulty+" + inner_->Url(); }

  FaultModel& faults() { return faults_; }
  size_t held() const { return held_.size(); }
  uint64_t dropped() const { return dropped_; }

 private:
  struct Held {
    int64_t release_at;  // a HandleTimeout call number, or steady-clock microseconds
    uint64_t order;
    PduType type;
    std::vector<uint8_t> bytes;
    bool operator>(const Held& o) const {
      return release_at != o.release_at ? release_at > o.release_at : order > o.order;
    }
  };
  // The HandleTimeout call number, or the steady clock in microseconds: a clock in whole
  // milliseconds would release a message up to 1 ms before its delay.
  int64_t Now() const;
  // When a message received now with this delay of the fault model is due, in Now()'s units.
  int64_t ReleaseAt(int64_t delay) const;

  void Receive(PduType type, std::span<const uint8_t> bytes);
  int Deliver(PduType type, std::span<const uint8_t> bytes) noexcept;

  std::unique_ptr<Transport> inner_;
  NodeAddress local_;
  FaultModel faults_;
  DelayUnit unit_;
  std::map<PduType, std::deque<Handler>> handlers_;
  std::priority_queue<Held, std::vector<Held>, std::greater<>> held_;
  int64_t calls_ = 0;
  uint64_t order_ = 0;
  uint64_t dropped_ = 0;
  int delivered_in_call_ = 0;
};

}  // namespace dt
