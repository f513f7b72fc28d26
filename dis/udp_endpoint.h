// UdpEndpoint: the gateway's DIS socket (plain POSIX UDP): bound to the DIS port, sending to a
// broadcast address or a multicast group, receiving whatever arrives on the port.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/result.h"

namespace dt::dis {

struct UdpEndpointConfig {
  std::string bind_address = "0.0.0.0";
  int port = 3000;
  std::string destination = "127.255.255.255";  // broadcast (SO_BROADCAST) or 224.0.0.0/4
  std::string interface_address = "127.0.0.1";  // multicast: joined and sent on
  int multicast_ttl = 1;
};

class UdpEndpoint {
 public:
  // Throws std::runtime_error naming the address and errno when the socket cannot be made,
  // bound or joined to the group; std::invalid_argument for an address that is not IPv4.
  explicit UdpEndpoint(const UdpEndpointConfig& config);
  ~UdpEndpoint();
  UdpEndpoint(const UdpEndpoint&) = delete;
  UdpEndpoint& operator=(const UdpEndpoint&) = delete;

  // One datagram to the destination; false (errno kept in last_error) when the kernel refuses it.
  bool Send(std::span<const uint8_t> datagram);
  // The next waiting datagram, valid until the next call; nullopt when none is waiting. A
  // datagram longer than a DIS PDU can be is given as kMaxPduSize + 1 bytes (the decoder
  // refuses it as too long).
  std::optional<std::span<const uint8_t>> Receive();
  int fd() const { return fd_; }
  int last_error() const { return last_error_; }
  bool multicast() const { return multicast_; }

 private:
  int fd_ = -1;
  bool multicast_ = false;
  int last_error_ = 0;
  std::vector<uint8_t> destination_;  // a sockaddr_in
  std::vector<uint8_t> buffer_;       // one datagram, allocated once
};

}  // namespace dt::dis
