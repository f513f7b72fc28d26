#include "pdu/faulty_transport.h"

#include "pdu/pdu_traits.h"

namespace dt {

FaultyTransport::FaultyTransport(std::unique_ptr<Transport> inner, NodeAddress local,
                                 FaultConfig faults, uint64_t seed)
    : inner_(std::move(inner)), local_(local), faults_(faults, seed) {}

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
      held_.push(Held{calls_ + static_cast<uint64_t>(d), order_++, type,
                      std::vector<uint8_t>(bytes.begin(), bytes.end())});
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
  auto r = inner_->HandleTimeout(held_.empty() ? timeout_ms : 0);
  if (!r) return r;
  while (!held_.empty() && held_.top().release_call <= calls_) {
    Held h = held_.top();
    held_.pop();
    delivered_in_call_ += Deliver(h.type, h.bytes);
  }
  return delivered_in_call_;
}

}  // namespace dt
