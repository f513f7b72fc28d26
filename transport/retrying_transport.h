// RetryingTransport: wraps any Transport so that a Publish the carrier cannot take now is queued
// and retried in order instead of lost or waited for.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "transport/transport.h"

namespace dt {

// A carrier may refuse a write for a while (a DDS writer whose history is full because a dead
// reader has not been unmatched yet returns Timeout at once rather than blocking). Such a failure
// says nothing about the peers, so the PDU is kept and sent later:
//  - Publish first sends what is queued on the PDU's channel; if the channel is clear it sends
//    the PDU, otherwise (or if sending fails) it queues the PDU behind the others and returns Ok.
//    So per channel, PDUs reach the inner transport in publish order.
//  - HandleTimeout retries every channel before and after waiting, and while anything is queued
//    waits no longer than kRetryIntervalMs; an event loop should call it at least that often
//    while queued() > 0 even if the fd is quiet.
//  - One call sends at most kMaxRetriesPerCall queued PDUs, so draining a long queue once the
//    carrier recovers is spread over calls instead of holding up one.
//  - At most max_queued PDUs wait (all channels together). A Publish that would exceed the bound
//    is refused with an Error naming the bound and counted in given_up: nothing is dropped
//    without the caller being told.
//  - A PDU over kMaxPduBytes is refused at once (retrying cannot help).
// Not thread-safe, like every Transport.
class RetryingTransport final : public Transport {
 public:
  static constexpr size_t kDefaultMaxQueued = 10000;
  static constexpr int kRetryIntervalMs = 5;
  static constexpr size_t kMaxRetriesPerCall = 64;

  struct Counters {
    size_t queued = 0;           // PDUs waiting now
    uint64_t retried = 0;        // queued PDUs later taken by the inner transport
    uint64_t failed_writes = 0;  // inner Publish calls that failed (first tries and retries)
    uint64_t given_up = 0;       // Publish calls refused because the queue was full
  };

  // Throws std::invalid_argument if max_queued is 0.
  explicit RetryingTransport(std::unique_ptr<Transport> inner,
                             size_t max_queued = kDefaultMaxQueued);

  Status Publish(PduType type, std::span<const uint8_t> bytes) override;
  void Subscribe(PduType type, Handler handler) override;
  Result<int> HandleTimeout(int timeout_ms) override;
  int Fd() const override { return inner_->Fd(); }
  std::string Url() const override { return "retrying+" + inner_->Url(); }

  // Sends what it can (at most kMaxRetriesPerCall) of every channel's queue now; returns how many
  // PDUs went.
  size_t Flush();
  size_t queued() const { return queued_; }
  Counters counters() const;
  Transport& inner() { return *inner_; }

 private:
  using Queue = std::deque<std::vector<uint8_t>>;
  // Sends the queue of one channel from its head until the inner transport refuses one or
  // `budget` PDUs went; returns how many went.
  size_t FlushChannel(size_t index, size_t budget);
  Status Enqueue(size_t index, std::span<const uint8_t> bytes, const std::string& why);

  std::unique_ptr<Transport> inner_;
  size_t max_queued_;
  std::array<Queue, kAllPduTypes.size()> queues_;
  size_t queued_ = 0;
  uint64_t retried_ = 0;
  uint64_t failed_writes_ = 0;
  uint64_t given_up_ = 0;
};

}  // namespace dt
