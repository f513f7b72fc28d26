// PduBus: typed PDUs over a Transport; handlers only ever see decoded, validated PDUs.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "pdu/dis_time.h"
#include "pdu/pdu_auth.h"
#include "pdu/validation.h"
#include "transport/transport.h"

namespace dt {

struct PduBusConfig {
  uint8_t exercise_id = 0;
  NodeAddress local;  // this node: stamped as every PDU's sender
  // > 0; positions outside [0, terrain_size_x_m] x [0, terrain_size_z_m] are dropped.
  double terrain_size_x_m = 0.0;
  double terrain_size_z_m = 0.0;
  // EarthMove posts beyond the grid's posts along x or z are dropped (0: not checked).
  int terrain_posts_x = 0;
  int terrain_posts_z = 0;
  // Transports echo a node's own PDUs back to it; by default the bus drops them (by the sender
  // field, first, before authentication and decoding).
  bool deliver_own = false;
  // Source of header.timestamp_dis; simulations pass a deterministic one.
  std::function<uint32_t()> clock = [] { return DisTimestampNow(); };
  std::chrono::milliseconds reject_log_interval{1000};
  // Authentication (pdu/pdu_auth.h). With a key every PDU sent carries a trailer and every PDU
  // received must carry a valid one; without (auth.key null) neither. Processes set it from the
  // exercise file's [auth] table.
  PduAuthConfig auth;
};

// Publishes typed PDUs (stamping the header, sender and sender_seq) and subscribes typed
// handlers. Every received message is authenticated (with a key), then decoded and validated; a
// rejected one is dropped, counted per reason, logged rate-limited and never reaches a handler.
// Same threading as Transport.
class PduBus {
 public:
  // Throws std::invalid_argument if terrain_size_x_m or terrain_size_z_m is not a positive finite
  // number, or for a bad authentication config (PduAuthenticator).
  PduBus(Transport& transport, PduBusConfig config);

  // Sets header (protocol version, exercise, type, time stamp), sender = local and the next
  // sender_seq, validates what will be sent (a bad PDU is refused, never sent), encodes, signs
  // (with a key) and publishes. Returns the sender_seq used.
  template <AnyPdu Pdu>
  Result<int64_t> Publish(Pdu pdu);

  // Adds a handler for validated PDUs of this type. Handlers must not throw.
  template <AnyPdu Pdu>
  void Subscribe(std::function<void(const Pdu&)> handler);

  // Transport::HandleTimeout: dispatches received PDUs to the handlers.
  Result<int> HandleTimeout(int timeout_ms) { return transport_.HandleTimeout(timeout_ms); }
  int Fd() const { return transport_.Fd(); }

  const RejectCounters& rejects() const { return reject_log_.counters(); }
  uint64_t accepted() const { return accepted_; }
  uint64_t own_echoes() const { return own_echoes_; }
  int64_t last_sender_seq() const { return sender_seq_; }
  const PduBusConfig& config() const { return config_; }
  // The authenticator; null when the bus runs without a key.
  const PduAuthenticator* authenticator() const { return auth_ ? &*auth_ : nullptr; }
  ValidationContext validation_context() const {
    return {config_.exercise_id, config_.terrain_size_x_m, config_.terrain_size_z_m,
            config_.terrain_posts_x, config_.terrain_posts_z};
  }

 private:
  template <AnyPdu Pdu>
  // A deque: a handler may subscribe another without invalidating the one running.
  using Handlers = std::deque<std::function<void(const Pdu&)>>;

  template <AnyPdu Pdu>
  void Receive(std::span<const uint8_t> bytes) noexcept;

  Transport& transport_;
  PduBusConfig config_;
  RejectLog reject_log_;
  std::optional<PduAuthenticator> auth_;
  std::vector<uint8_t> encode_buffer_;  // reused: no allocation per published PDU
  int64_t sender_seq_ = 0;
  uint64_t accepted_ = 0;
  uint64_t own_echoes_ = 0;
  std::tuple<Handlers<dtpdu::construct_t>, Handlers<dtpdu::update_t>, Handlers<dtpdu::destruct_t>,
             Handlers<dtpdu::max_feature_t>, Handlers<dtpdu::playback_t>,
             Handlers<dtpdu::anti_entropy_t>, Handlers<dtpdu::vehicle_state_t>,
             Handlers<dtpdu::earth_move_t>>
      handlers_;
};

template <AnyPdu Pdu>
Result<int64_t> PduBus::Publish(Pdu pdu) {
  if (sender_seq_ >= kMaxSerial) {
    return Error{fmt::format("node {} has sent {} PDUs: sender_seq is exhausted",
                             config_.local.ToString(), sender_seq_)};
  }
  pdu.header.protocol_version = kProtocolVersion;
  pdu.header.exercise_id = config_.exercise_id;
  pdu.header.pdu_type = static_cast<uint8_t>(PduTraits<Pdu>::kType);
  pdu.header.timestamp_dis = static_cast<int32_t>(config_.clock());
  pdu.sender.site = static_cast<int16_t>(config_.local.site);
  pdu.sender.host = static_cast<int16_t>(config_.local.host);
  pdu.sender_seq = sender_seq_ + 1;
  if (auto r = Validate(pdu, validation_context())) {
    return Error{fmt::format("refusing to send an invalid {} PDU: {} ({})",
                             PduTypeName(PduTraits<Pdu>::kType), RejectReasonName(r->reason),
                             r->detail)};
  }
  EncodePduInto(pdu, encode_buffer_);
  if (auth_) auth_->Sign(encode_buffer_);
  if (auto s = transport_.Publish(PduTraits<Pdu>::kType, encode_buffer_); !s) return s.error();
  return ++sender_seq_;
}

template <AnyPdu Pdu>
void PduBus::Subscribe(std::function<void(const Pdu&)> handler) {
  auto& list = std::get<Handlers<Pdu>>(handlers_);
  if (list.empty()) {
    transport_.Subscribe(PduTraits<Pdu>::kType,
                         [this](std::span<const uint8_t> bytes) { Receive<Pdu>(bytes); });
  }
  list.push_back(std::move(handler));
}

template <AnyPdu Pdu>
void PduBus::Receive(std::span<const uint8_t> bytes) noexcept {
  // Its own PDUs, echoed by the transport, could reach no handler: dropped before they cost a
  // MAC or a decode (so a forgery naming this node as sender counts as an echo).
  if (!config_.deliver_own) {
    if (const auto sender = PeekSender(bytes); sender && *sender == config_.local) {
      ++own_echoes_;
      return;
    }
  }
  if (auth_) {
    if (auto r = auth_->Verify(bytes, bytes)) {
      reject_log_.Record(PduTraits<Pdu>::kType, *r);
      return;
    }
  }
  Pdu pdu;
  if (auto r = DecodeAndValidate(bytes, validation_context(), pdu)) {
    reject_log_.Record(PduTraits<Pdu>::kType, *r);
    return;
  }
  ++accepted_;
  const auto& list = std::get<Handlers<Pdu>>(handlers_);
  for (size_t i = 0; i < list.size(); ++i) list[i](pdu);
}

}  // namespace dt
