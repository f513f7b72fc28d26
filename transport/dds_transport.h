// DdsTransport: the Transport over Cyclone DDS, reliable and keep-all, one typed topic per PDU
// type.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "transport/transport.h"

namespace dt {

struct DdsConfig {
  uint32_t domain_id = 0;
  // A Cyclone DDS XML configuration file; empty: CYCLONEDDS_URI or Cyclone's defaults.
  std::string config_file;
  // Construct, Update and Destruct topics transient-local: every writer keeps the latest sample
  // of each feature and gives them to readers that join later. Readers then match only durable
  // writers, so an exercise sets it for every process or for none. (docs/pdu.md "Durability".)
  bool durable_features = false;
};

// Parses "dds://<domain>[?<option>[&<option>]]", options config=<file> and durable=0|1. Throws
// std::invalid_argument naming the URL.
DdsConfig ParseDdsUrl(std::string_view url);

// Cyclone DDS settings every DdsTransport's domain starts from (docs/pdu.md "Cyclone DDS"); a
// configuration file (or CYCLONEDDS_URI) given by the user comes after them and overrides them.
//  - LeaseDuration 3 s (Cyclone's default is 10 s): a killed or stopped process's readers are
//    unmatched 3 s after its last message, and only until then do they hold writers back.
//    Cyclone re-announces a participant every 4/5 of its lease (2.4 s), and any data renews it.
//  - WhcHigh = WhcHighInit 4 MB (defaults 500 kB, growing from 30 kB): how much unacknowledged
//    data a writer may hold before dds_write refuses. A dead reader acknowledges nothing until
//    it is unmatched; 4 MB holds a lease's worth of a server's playback bursts (about 20 000
//    PDUs), so in practice nothing is refused, and what is gets queued by RetryingTransport.
inline constexpr std::string_view kDdsDomainDefaults =
    "<CycloneDDS><Domain id=\"any\"><Discovery><LeaseDuration>3s</LeaseDuration></Discovery>"
    "<Internal><Watermarks><WhcHigh>4MB</WhcHigh><WhcHighInit>4MB</WhcHighInit></Watermarks>"
    "</Internal></Domain></CycloneDDS>";

// The configuration a DdsTransport's domain is created with: kDdsDomainDefaults, then the
// config file or, if none, CYCLONEDDS_URI (Cyclone's comma-separated list; later wins).
std::string DomainConfig(const DdsConfig& config);

// One participant; per PDU type a topic named ChannelName(exercise, type) of the PDU's own IDL
// type (dtpdu_dds::<lcm name>, generated from the .lcm file; features keyed by their ID), a
// writer and, once subscribed, a reader. The Transport still moves bytes: Publish decodes the
// LCM bytes into the sample (refusing bytes that are not a PDU of the channel's type) and
// carries whatever follows the PDU (at most dds_codec::kMaxAuthBytes) in its `auth` member;
// receiving re-encodes the sample, so handlers get the very bytes published. Validation stays
// with PduBus, as on every transport. QoS: reliable with no blocking
// (a write that would wait for acknowledgements fails with Timeout at once and writes nothing),
// keep-all history, volatile. A data-available listener (on Cyclone's threads) only signals an
// eventfd; samples are taken and handlers run in HandleTimeout on the caller's thread.
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
  // Readers the writer of `type` is matched with now (-1 if DDS cannot tell).
  int MatchedReaders(PduType type) const;

 private:
  struct PerType {
    int32_t topic = 0;
    int32_t writer = 0;
    int32_t reader = 0;
    std::deque<Handler> handlers;
  };
  int TakeAll(PduType type, PerType& per_type);
  bool Durable(PduType type) const;

  DdsConfig config_;
  uint8_t exercise_id_;
  std::vector<uint8_t> bytes_;  // a received sample re-encoded, reused
  uint64_t undecodable_ = 0;
  int32_t domain_ = 0;  // non-zero when this transport created the domain
  int32_t participant_ = 0;
  int event_fd_ = -1;
  std::array<PerType, kAllPduTypes.size()> types_;
};

}  // namespace dt
