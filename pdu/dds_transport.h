// DdsTransport: the Transport over Cyclone DDS, reliable and keep-all, one topic per PDU type.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>

#include "pdu/transport.h"

namespace dt {

struct DdsConfig {
  uint32_t domain_id = 0;
  // A Cyclone DDS XML configuration file; empty: CYCLONEDDS_URI or Cyclone's defaults.
  std::string config_file;
};

// Parses "dds://<domain>[?config=<file>]". Throws std::invalid_argument naming the URL.
DdsConfig ParseDdsUrl(std::string_view url);

// One participant; per PDU type a topic named ChannelName(exercise, type) of the IDL type
// dtpdu_dds::Pdu (the LCM-encoded bytes, so decoding and validation are the transport's
// business nowhere), a writer and, once subscribed, a reader. QoS: reliable, keep-all history,
// volatile. A data-available listener (on Cyclone's threads) only signals an eventfd; samples are
// taken and handlers run in HandleTimeout on the caller's thread.
class DdsTransport final : public Transport {
 public:
  // Throws std::runtime_error (with Cyclone's error text) if DDS entities cannot be created.
  DdsTransport(DdsConfig config, uint8_t exercise_id);
  ~DdsTransport() override;
  DdsTransport(const DdsTransport&) = delete;
  DdsTransport& operator=(const DdsTransport&) = delete;

  Status Publish(PduType type, std::span<const uint8_t> bytes) override;
  void Subscribe(PduType type, Handler handler) override;
  Result<int> HandleTimeout(int timeout_ms) override;
  int Fd() const override { return event_fd_; }
  std::string Url() const override;

  // Waits (on a DDS waitset, at most timeout_ms) until the writer of `type` is matched by at least
  // `readers` readers, this transport's own reader included. Volatile data written before a
  // reader is matched never reaches it, so a sender that must not lose its first PDUs waits here.
  bool WaitForReaders(PduType type, int readers, int timeout_ms);

 private:
  struct PerType {
    int32_t topic = 0;
    int32_t writer = 0;
    int32_t reader = 0;
    std::deque<Handler> handlers;
  };
  int TakeAll(PduType type, PerType& per_type);

  DdsConfig config_;
  uint8_t exercise_id_;
  int32_t domain_ = 0;  // non-zero when this transport created the domain
  int32_t participant_ = 0;
  int event_fd_ = -1;
  std::array<PerType, kAllPduTypes.size()> types_;
};

}  // namespace dt
