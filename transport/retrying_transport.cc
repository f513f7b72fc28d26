#include "transport/retrying_transport.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"
#include "log/log.h"

namespace dt {
namespace {

size_t IndexOf(PduType type) {
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    if (kAllPduTypes[i] == type) return i;
  }
  DT_UNREACHABLE();  // every PduType is in kAllPduTypes
}

}  // namespace

RetryingTransport::RetryingTransport(std::unique_ptr<Transport> inner, size_t max_queued)
    : inner_(std::move(inner)), max_queued_(max_queued) {
  if (max_queued_ == 0) {
    throw std::invalid_argument("RetryingTransport: max_queued must be at least 1");
  }
}

RetryingTransport::Counters RetryingTransport::counters() const {
  return Counters{queued_, retried_, failed_writes_, given_up_};
}

Status RetryingTransport::Enqueue(size_t index, std::span<const uint8_t> bytes,
                                  const std::string& why) {
  const PduType type = kAllPduTypes[index];
  if (queued_ >= max_queued_) {
    ++given_up_;
    return Error{
        fmt::format("{} PDU refused: {} PDUs already wait for the transport (the bound); "
                    "last failure: {}",
                    PduTypeName(type), queued_, why)};
  }
  if (queued_ == 0) {
    // Once per episode, not per PDU: a blocked writer may fail thousands of times.
    DT_LOG_WARN("transport write failed, queueing PDUs for retry: {}", why);
  }
  queues_[index].emplace_back(bytes.begin(), bytes.end());
  ++queued_;
  return Status::Ok();
}

size_t RetryingTransport::FlushChannel(size_t index, size_t budget) {
  Queue& q = queues_[index];
  size_t sent = 0;
  while (!q.empty() && sent < budget) {
    if (!inner_->Publish(kAllPduTypes[index], q.front())) {
      ++failed_writes_;
      break;
    }
    q.pop_front();
    --queued_;
    ++retried_;
    ++sent;
  }
  return sent;
}

size_t RetryingTransport::Flush() {
  if (queued_ == 0) return 0;
  size_t sent = 0;
  for (size_t i = 0; i < queues_.size(); ++i) sent += FlushChannel(i, kMaxRetriesPerCall - sent);
  if (queued_ == 0) {
    DT_LOG_INFO("transport writes recovered: every queued PDU sent ({} retried so far)", retried_);
  }
  return sent;
}

Status RetryingTransport::Publish(PduType type, std::span<const uint8_t> bytes) {
  if (bytes.size() > kMaxPduBytes) {
    return Error{fmt::format("{} PDU of {} bytes exceeds the {}-byte single-datagram limit",
                             PduTypeName(type), bytes.size(), kMaxPduBytes)};
  }
  const size_t index = IndexOf(type);
  if (!queues_[index].empty()) {
    FlushChannel(index, kMaxRetriesPerCall);
    if (!queues_[index].empty()) {
      return Enqueue(index, bytes, "earlier PDUs of this channel are still queued");
    }
    if (queued_ == 0) {
      DT_LOG_INFO("transport writes recovered: every queued PDU sent ({} retried so far)",
                  retried_);
    }
  }
  Status s = inner_->Publish(type, bytes);
  if (s) return s;
  ++failed_writes_;
  return Enqueue(index, bytes, s.error().message);
}

void RetryingTransport::Subscribe(PduType type, Handler handler) {
  inner_->Subscribe(type, std::move(handler));
}

Result<int> RetryingTransport::HandleTimeout(int timeout_ms) {
  Flush();
  const int wait_ms = queued_ > 0 ? std::min(timeout_ms, kRetryIntervalMs) : timeout_ms;
  Result<int> r = inner_->HandleTimeout(wait_ms);
  // Acknowledgements received while waiting may have made room.
  Flush();
  return r;
}

}  // namespace dt
