#include "dis/udp_endpoint.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "dis/dis_pdu.h"

namespace dt::dis {
namespace {

in_addr Parse(const std::string& text, const char* what) {
  in_addr a{};
  if (inet_pton(AF_INET, text.c_str(), &a) != 1) {
    throw std::invalid_argument(fmt::format("DIS {} \"{}\" is not an IPv4 address", what, text));
  }
  return a;
}

[[noreturn]] void Fail(int fd, const std::string& what) {
  const int e = errno;
  if (fd >= 0) ::close(fd);
  throw std::runtime_error(fmt::format("DIS socket: {}: {}", what, std::strerror(e)));
}

}  // namespace

UdpEndpoint::UdpEndpoint(const UdpEndpointConfig& c) {
  const in_addr bind_at = Parse(c.bind_address, "bind_address");
  const in_addr dest = Parse(c.destination, "destination");
  const in_addr iface = Parse(c.interface_address, "interface_address");
  multicast_ = (ntohl(dest.s_addr) >> 28) == 0xE;
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) Fail(-1, "socket");
  const int one = 1;
  // Other DIS tools on this host listen on the same port.
  if (::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0) Fail(fd_, "SO_REUSEADDR");
  if (::setsockopt(fd_, SOL_SOCKET, SO_REUSEPORT, &one, sizeof one) != 0) Fail(fd_, "SO_REUSEPORT");
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_port = htons(static_cast<uint16_t>(c.port));
  local.sin_addr = bind_at;
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    Fail(fd_, fmt::format("bind {}:{}", c.bind_address, c.port));
  }
  if (multicast_) {
    ip_mreq m{};
    m.imr_multiaddr = dest;
    m.imr_interface = iface;
    if (::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &m, sizeof m) != 0) {
      Fail(fd_, fmt::format("join {} on {}", c.destination, c.interface_address));
    }
    if (::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_IF, &iface, sizeof iface) != 0) {
      Fail(fd_, "IP_MULTICAST_IF " + c.interface_address);
    }
    const unsigned char ttl = static_cast<unsigned char>(c.multicast_ttl);
    const unsigned char loop = 1;  // DIS tools on this host see the exercise too
    if (::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0 ||
        ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0) {
      Fail(fd_, "multicast TTL / loop");
    }
  } else if (::setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) != 0) {
    Fail(fd_, "SO_BROADCAST");
  }
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(c.port));
  to.sin_addr = dest;
  destination_.resize(sizeof to);
  std::memcpy(destination_.data(), &to, sizeof to);
}

UdpEndpoint::~UdpEndpoint() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpEndpoint::Send(std::span<const uint8_t> datagram) {
  const ssize_t n = ::sendto(fd_, datagram.data(), datagram.size(), 0,
                             reinterpret_cast<const sockaddr*>(destination_.data()),
                             static_cast<socklen_t>(destination_.size()));
  if (n != static_cast<ssize_t>(datagram.size())) {
    last_error_ = errno;
    return false;
  }
  return true;
}

std::optional<std::span<const uint8_t>> UdpEndpoint::Receive() {
  // One more than a DIS PDU can be, so an oversized datagram is seen as such, not cut to fit.
  if (buffer_.empty()) buffer_.resize(kMaxPduSize + 1);
  const ssize_t n = ::recv(fd_, buffer_.data(), buffer_.size(), MSG_TRUNC);
  if (n < 0) return std::nullopt;
  return std::span<const uint8_t>(buffer_.data(), std::min(static_cast<size_t>(n), buffer_.size()));
}

}  // namespace dt::dis
