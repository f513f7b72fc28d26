#include "transport/pdu_bus.h"

#include <cmath>

#include "log/log.h"

namespace dt {

PduBus::PduBus(Transport& transport, PduBusConfig config)
    : transport_(transport), config_(std::move(config)), reject_log_(config_.reject_log_interval) {
  for (const auto& [name, size_m] : {std::pair{"terrain_size_x_m", config_.terrain_size_x_m},
                                     std::pair{"terrain_size_z_m", config_.terrain_size_z_m}}) {
    if (!std::isfinite(size_m) || !(size_m > 0.0)) {
      throw std::invalid_argument(fmt::format("PduBus: {} = {} must be positive", name, size_m));
    }
  }
  if (!config_.clock) throw std::invalid_argument("PduBus: clock is empty");
  if (config_.flight_datagrams < 1) {
    throw std::invalid_argument(
        fmt::format("PduBus: flight_datagrams = {} must be at least 1", config_.flight_datagrams));
  }
  if (config_.auth.key) auth_.emplace(config_.local, config_.auth);
}

Result<int> PduBus::HandleTimeout(int timeout_ms) {
  if (timeout_ms != 0) Flush();  // nothing waits in a batch while the loop sleeps
  Batch answers(*this);
  return transport_.HandleTimeout(timeout_ms);
}

Status PduBus::Queue(PduType type) {
  const size_t trailer = auth_ ? kAuthTrailerBytes : 0;
  if (encode_buffer_.size() + trailer > kMaxPduBytes) {
    return Error{fmt::format("{} PDU of {} bytes exceeds the {}-byte single-datagram limit",
                             PduTypeName(type), encode_buffer_.size() + trailer, kMaxPduBytes)};
  }
  // Behind another PDU, it goes as the bytes where it differs from that one when that is shorter
  // (docs/pdu.md "Member deltas"): a burst's Constructs differ in a few fields.
  size_t member_bytes = encode_buffer_.size();
  bool as_delta = false;
  if (waiting_count_ > 0) {
    EncodeMemberDelta(waiting_[waiting_count_ - 1].bytes, encode_buffer_, delta_buffer_);
    as_delta = delta_buffer_.size() < member_bytes;
    if (as_delta) member_bytes = delta_buffer_.size();
  }
  if (waiting_bytes_ + kBatchMemberBytes + member_bytes + trailer > kMaxPduBytes) {
    CloseDatagram();
    if (flight_count_ >= static_cast<size_t>(config_.flight_datagrams)) SendFlight();
    as_delta = false;  // the first of a datagram goes whole
    member_bytes = encode_buffer_.size();
  }
  if (waiting_count_ == waiting_.size()) waiting_.emplace_back();
  Waiting& w = waiting_[waiting_count_++];
  w.type = type;
  w.bytes.assign(encode_buffer_.begin(), encode_buffer_.end());
  w.as_delta = as_delta;
  if (as_delta) w.delta.swap(delta_buffer_);
  waiting_bytes_ += kBatchMemberBytes + member_bytes;
  return Status::Ok();
}

void PduBus::Flush() noexcept {
  CloseDatagram();
  SendFlight();
}

void PduBus::CloseDatagram() noexcept {
  if (waiting_count_ == 0) return;
  if (flight_count_ == flight_.size()) flight_.emplace_back();
  Datagram& d = flight_[flight_count_++];
  d.pdus = waiting_count_;
  if (waiting_count_ == 1) {
    // A lone PDU is swapped in, not copied: nothing extra on a single change's way.
    d.type = waiting_[0].type;
    d.bytes.swap(waiting_[0].bytes);
  } else {
    members_.clear();
    for (size_t i = 0; i < waiting_count_; ++i) {
      const Waiting& w = waiting_[i];
      members_.push_back(w.as_delta ? BatchMember{w.type, w.delta, MemberEncoding::kDelta}
                                    : BatchMember{w.type, w.bytes, MemberEncoding::kWhole});
    }
    d.type = PduType::kBatch;
    EncodeBatchInto(config_.exercise_id, config_.clock(), config_.local, members_, d.bytes);
  }
  waiting_count_ = 0;
  waiting_bytes_ = kBatchBaseBytes;
  if (auth_) auth_->Sign(d.bytes);
}

void PduBus::SendFlight() noexcept {
  // Handlers run inside HandleTimeout, never inside a carrier's Publish (Transport's contract),
  // so nothing is published while a flight is sent; should a carrier break that, what a handler
  // queues joins this flight (the loop rereads the count) rather than a second one overtaking it.
  if (sending_flight_) return;
  sending_flight_ = true;
  for (size_t i = 0; i < flight_count_; ++i) {
    const PduType type = flight_[i].type;
    const size_t pdus = flight_[i].pdus;
    if (auto s = transport_.Publish(type, flight_[i].bytes); !s) {
      ++send_failures_;
      DT_LOG_WARN("sending {} PDU(s) in one datagram failed: {}", pdus, s.error().message);
      continue;
    }
    if (type == PduType::kBatch) ++batches_sent_;
  }
  flight_count_ = 0;
  sending_flight_ = false;
}

void PduBus::ReceiveBatch(std::span<const uint8_t> bytes) noexcept {
  if (!config_.deliver_own) {
    if (const auto sender = PeekSender(bytes); sender && *sender == config_.local) {
      ++own_echoes_;
      return;
    }
  }
  if (auth_) {
    if (auto r = auth_->Verify(bytes, bytes)) {
      reject_log_.Record(PduType::kBatch, *r);
      return;
    }
  }
  std::vector<MemberPdu> nested;
  const bool outermost = !receiving_;
  std::vector<MemberPdu>& members = outermost ? received_ : nested;
  if (auto r = DecodeBatch(bytes, validation_context(), members)) {
    Refuse(PduType::kBatch, bytes, *r);
    return;
  }
  ++batches_received_;
  receiving_ = true;
  for (const MemberPdu& m : members) {
    std::visit(
        [this](const auto& pdu) {
          ++accepted_;
          Deliver(pdu);
        },
        m);
  }
  if (outermost) receiving_ = false;
}

void PduBus::Refuse(PduType channel, std::span<const uint8_t> bytes, const Rejection& r) noexcept {
  reject_log_.Record(channel, r);
  if (r.reason != RejectReason::kWrongProtocolVersion) return;
  const std::optional<NodeAddress> sender = PeekSender(bytes);
  if (!sender || wrong_protocol_senders_.size() >= kMaxWrongProtocolSenders) return;
  if (!wrong_protocol_senders_.insert(*sender).second) return;
  DT_LOG_ERROR(
      "refusing every PDU of {}: {}. It cannot take part in this exercise until both run one "
      "release (docs/pdu.md \"Protocol version\"); its PDUs are counted as rejected_{}",
      sender->ToString(), r.detail, RejectReasonName(r.reason));
}

}  // namespace dt
