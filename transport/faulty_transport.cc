#include "transport/faulty_transport.h"

#include <algorithm>
#include <chrono>

#include "pdu/pdu_traits.h"

namespace dt {

FaultyTransport::FaultyTransport(std::unique_ptr<Transport> inner, NodeAddress local,
                                 FaultConfig faults, uint64_t seed, DelayUnit unit)
    : inner_(std::move(inner)), local_(local), faults_(faults, seed), unit_(unit) {}

int64_t FaultyTransport::Now() const {
  if (unit_ == DelayUnit::kHandleCalls) return calls_;
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int64_t FaultyTransport::ReleaseAt(int64_t delay) const {
  if (unit_ == DelayUnit::kHandleCalls) return Now() + delay;
  return Now() + delay * 1000 + 1;  // Now() truncates: never released before the delay
}

Status FaultyTransport::Publish(PduType type, std::span<const uint8_t> bytes) {
  return inner_->Publish(type, bytes);
}

void FaultyTransport::Subscribe(PduType type, Handler handler) {
  auto& list = handlers_[type];
  if (list.empty()) {
    inner_->Subscribe(type, [this, type](std::span<const uint8_t> b) { Receive(type, b); });
  }
  list.push_back(std::move(handler));
}

void FaultyTransport::Receive(PduType type, std::span<const uint8_t> bytes) {
  // Bytes too short to name a sender come from no node: fault them like a stranger's, and let
  // validation reject them.
  const NodeAddress sender = PeekSender(bytes).value_or(NodeAddress{0xFFFF, 0xFFFF});
  const std::vector<int64_t> delays = faults_.Fate(sender, local_);
  if (delays.empty()) ++dropped_;
  for (int64_t d : delays) {
    if (d == 0) {
      delivered_in_call_ += Deliver(type, bytes);
    } else {
      held_.push(
          Held{ReleaseAt(d), order_++, type, std::vector<uint8_t>(bytes.begin(), bytes.end())});
    }
  }
}

int FaultyTransport::Deliver(PduType type, std::span<const uint8_t> bytes) noexcept {
  auto it = handlers_.find(type);
  if (it == handlers_.end()) return 0;
  for (size_t i = 0; i < it->second.size(); ++i) it->second[i](bytes);
  return 1;
}

Result<int> FaultyTransport::HandleTimeout(int timeout_ms) {
  ++calls_;
  delivered_in_call_ = 0;
  int wait_ms = timeout_ms;
  if (!held_.empty()) {
    // Wait for new traffic no longer than until the next held message is due.
    const int64_t until_release_us = held_.top().release_at - Now();
    wait_ms =
        unit_ == DelayUnit::kHandleCalls
            ? 0
            : static_cast<int>(std::clamp<int64_t>((until_release_us + 999) / 1000, 0, timeout_ms));
  }
  auto r = inner_->HandleTimeout(wait_ms);
  if (!r) return r;
  const int64_t now = Now();
  while (!held_.empty() && held_.top().release_at <= now) {
    Held h = held_.top();
    held_.pop();
    delivered_in_call_ += Deliver(h.type, h.bytes);
  }
  return delivered_in_call_;
}

}  // namespace dt
