// PduBus: typed PDUs over a Transport; handlers only ever see decoded, validated PDUs.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <set>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "pdu/batch.h"
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
  // Inside a PduBus::Batch, PDUs wait and go out packed into as few datagrams as fit
  // (docs/pdu.md "Batch"). false: each goes alone even there, as for a durable DDS exercise, whose
  // feature topics keep one instance per feature and so must carry features one by one.
  bool batch = true;
  // Inside a Batch, full datagrams wait too and leave together, this many at a time, the rest
  // when the outermost Batch ends: each receiving process then wakes once for several datagrams,
  // not once for each (docs/pdu.md "Flights"). 32 datagrams of at most kMaxPduBytes (45 KB, 75 KB
  // as the kernel counts them) fit a socket's default receive buffer (208 KB) well. At least 1 (1:
  // each leaves as soon as it is full).
  int flight_datagrams = 32;
};

// Publishes typed PDUs (stamping the header, sender and sender_seq) and subscribes typed
// handlers. Every received message is authenticated (with a key), then decoded and validated; a
// rejected one is dropped, counted per reason, logged rate-limited and never reaches a handler.
// A batch (docs/pdu.md "Batch") is authenticated once, then taken whole, its members handed to
// the handlers in order, or refused whole. Same threading as Transport.
class PduBus {
 public:
  // While one lives (they nest), PDUs published wait and go out packed into batches of at most
  // kMaxPduBytes, one authentication trailer each, in flights of flight_datagrams; when the
  // outermost ends, what waits is sent.
  // A lone PDU goes out as itself, as without a batch. Processes hold one over each tick, and
  // HandleTimeout over the dispatch of what it receives, so every PDU leaves within the tick it
  // was made in.
  class Batch {
   public:
    explicit Batch(PduBus& bus) : bus_(bus) { ++bus_.batch_depth_; }
    ~Batch() {
      if (--bus_.batch_depth_ == 0) bus_.Flush();
    }
    Batch(const Batch&) = delete;
    Batch& operator=(const Batch&) = delete;

   private:
    PduBus& bus_;
  };

  // Throws std::invalid_argument if terrain_size_x_m or terrain_size_z_m is not a positive finite
  // number, or for a bad authentication config (PduAuthenticator).
  PduBus(Transport& transport, PduBusConfig config);

  // Sets header (protocol version, exercise, type, time stamp), sender = local and the next
  // sender_seq, validates what will be sent (a bad PDU is refused, never sent), encodes, signs
  // (with a key) and publishes. Returns the sender_seq used. Inside a Batch the PDU waits for the
  // batch's datagram: a carrier's refusal of that is logged and counted (send_failures), not
  // returned; a PDU that cannot fit one datagram is refused here either way.
  template <AnyPdu Pdu>
  Result<int64_t> Publish(Pdu pdu);

  // Sends what waits inside a Batch now (Batch and HandleTimeout call it).
  void Flush() noexcept;

  // Adds a handler for validated PDUs of this type. Handlers must not throw.
  template <AnyPdu Pdu>
  void Subscribe(std::function<void(const Pdu&)> handler);

  // Transport::HandleTimeout: dispatches received PDUs to the handlers. Sends what waits in a
  // batch before it waits for traffic, and what the handlers publish (answers) after, packed.
  Result<int> HandleTimeout(int timeout_ms);
  int Fd() const { return transport_.Fd(); }

  const RejectCounters& rejects() const { return reject_log_.counters(); }
  uint64_t accepted() const { return accepted_; }
  uint64_t own_echoes() const { return own_echoes_; }
  // Datagrams of several PDUs sent and taken; those refused are in rejects() (channel BATCH).
  uint64_t batches_sent() const { return batches_sent_; }
  uint64_t batches_received() const { return batches_received_; }
  // Datagrams the carrier refused when a batch was flushed.
  uint64_t send_failures() const { return send_failures_; }
  // Senders refused for speaking another protocol version (each logged once, as an error), the
  // first kMaxWrongProtocolSenders of them: datagrams naming ever new senders (a hostile flood on
  // an exercise without a key) are still refused and counted, but neither kept nor logged.
  static constexpr size_t kMaxWrongProtocolSenders = 256;
  const std::set<NodeAddress>& wrong_protocol_senders() const { return wrong_protocol_senders_; }
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
  void ReceiveBatch(std::span<const uint8_t> bytes) noexcept;
  template <AnyPdu Pdu>
  void Deliver(const Pdu& pdu) noexcept;
  // Counts and logs a refusal; a sender of another protocol version is named once, as an error.
  void Refuse(PduType channel, std::span<const uint8_t> bytes, const Rejection& r) noexcept;
  // Checks `encode_buffer_` (a PDU of `type`) against the datagram limit and queues it in the
  // batch, closing the datagram being filled first when it would not fit.
  Status Queue(PduType type);
  // Packs what waits into one datagram (a lone PDU as itself), signs it and adds it to the flight.
  void CloseDatagram() noexcept;
  // Publishes the flight's datagrams in order.
  void SendFlight() noexcept;

  struct Waiting {
    PduType type = PduType::kConstruct;
    std::vector<uint8_t> bytes;  // its LCM encoding; the vectors are kept for the next batch
    std::vector<uint8_t> delta;  // against the PDU before it, when that is the shorter
    bool as_delta = false;
  };

  Transport& transport_;
  PduBusConfig config_;
  RejectLog reject_log_;
  std::optional<PduAuthenticator> auth_;
  std::vector<uint8_t> encode_buffer_;  // reused: no allocation per published PDU
  std::vector<uint8_t> delta_buffer_;   // reused by Queue
  int64_t sender_seq_ = 0;
  uint64_t accepted_ = 0;
  uint64_t own_echoes_ = 0;
  int batch_depth_ = 0;
  std::vector<Waiting> waiting_;  // the first waiting_count_ wait
  size_t waiting_count_ = 0;
  size_t waiting_bytes_ = kBatchBaseBytes;  // the batch_t they would make
  std::vector<BatchMember> members_;        // reused by CloseDatagram
  // Closed datagrams waiting to leave: the first flight_count_ (vectors kept for the next).
  struct Datagram {
    PduType type = PduType::kBatch;
    size_t pdus = 0;
    std::vector<uint8_t> bytes;
  };
  std::vector<Datagram> flight_;
  size_t flight_count_ = 0;
  bool sending_flight_ = false;
  // The members of the batch being handed on, reused batch to batch (no allocation per batch
  // received). A handler that makes this bus receive again, through a carrier that delivers
  // within Publish, decodes into a vector of its own: these are still being handed on.
  std::vector<MemberPdu> received_;
  bool receiving_ = false;
  bool batch_subscribed_ = false;
  uint64_t batches_sent_ = 0;
  uint64_t batches_received_ = 0;
  uint64_t send_failures_ = 0;
  std::set<NodeAddress> wrong_protocol_senders_;
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
  if (batch_depth_ > 0 && config_.batch) {
    if (auto s = Queue(PduTraits<Pdu>::kType); !s) return s.error();
    return ++sender_seq_;
  }
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
  if (!batch_subscribed_) {
    batch_subscribed_ = true;
    transport_.Subscribe(PduType::kBatch,
                         [this](std::span<const uint8_t> bytes) { ReceiveBatch(bytes); });
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
    Refuse(PduTraits<Pdu>::kType, bytes, *r);
    return;
  }
  ++accepted_;
  Deliver(pdu);
}

template <AnyPdu Pdu>
void PduBus::Deliver(const Pdu& pdu) noexcept {
  const auto& list = std::get<Handlers<Pdu>>(handlers_);
  for (size_t i = 0; i < list.size(); ++i) list[i](pdu);
}

}  // namespace dt
