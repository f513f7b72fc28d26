// Transport: the one small interface every PDU carrier (memq, udpm, DDS, simulated) implements.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "base/result.h"
#include "pdu/pdu_type.h"

namespace dt {

// Moves encoded PDUs (raw bytes) on one channel per PDU type. Not thread-safe: one thread
// publishes, subscribes and calls HandleTimeout, and every handler runs on that thread inside
// HandleTimeout. Every implementation delivers a PDU to the publisher's own subscribers too (as
// LCM does); PduBus drops those echoes unless asked not to.
class Transport {
 public:
  // Receives the bytes of one PDU; the span is valid only during the call. Handlers must not
  // throw: they are called from noexcept code, so an exception terminates the process.
  using Handler = std::function<void(std::span<const uint8_t> bytes)>;

  virtual ~Transport() = default;

  // Sends bytes on the channel of `type`. Refuses more than kMaxPduBytes bytes with an Error,
  // and reports a failure of the underlying transport as an Error.
  virtual Status Publish(PduType type, std::span<const uint8_t> bytes) = 0;

  // Adds a handler for every PDU received on the channel of `type`. Several handlers per type
  // are allowed; each sees every message, in the order subscribed.
  virtual void Subscribe(PduType type, Handler handler) = 0;

  // Waits up to timeout_ms (0: do not wait) for traffic, then dispatches everything that has
  // arrived. Returns the number of messages dispatched (0 on timeout) or an Error.
  virtual Result<int> HandleTimeout(int timeout_ms) = 0;

  // A file descriptor that becomes readable when HandleTimeout has work, for poll/epoll loops.
  // Valid for the life of the transport; never read it directly.
  virtual int Fd() const = 0;

  // The configuration string this transport was made from, for logs.
  virtual std::string Url() const = 0;
};

// Makes a transport from a URL-like string (docs/pdu.md):
//   "memq://"                                  in-process, this object only (LCM memq)
//   "udpm://239.255.76.67:7667?ttl=0"          LCM UDP multicast (the default; ttl=0 stays on
//                                              the host, ttl=1 spans the LAN)
//   "dds://<domain>[?config=<file.xml>][&durable=1]"  Cyclone DDS, reliable, keep-all
// Channels carry exercise_id. Throws std::invalid_argument for a malformed URL and
// std::runtime_error when the transport cannot be created (the message names the URL).
std::unique_ptr<Transport> MakeTransport(std::string_view url, uint8_t exercise_id);

// The default deployment URL.
inline constexpr std::string_view kDefaultTransportUrl = "udpm://239.255.76.67:7667?ttl=0";

}  // namespace dt
