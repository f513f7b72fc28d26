#include "runtime/control_server.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {
namespace {

sockaddr_un Address(const std::filesystem::path& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const std::string s = path.string();
  if (s.empty() || s.size() >= sizeof(addr.sun_path)) {
    throw std::invalid_argument(fmt::format(
        "control socket path \"{}\" is {} bytes; a Unix socket path must be 1..{} bytes", s,
        s.size(), sizeof(addr.sun_path) - 1));
  }
  std::memcpy(addr.sun_path, s.data(), s.size());
  return addr;
}

}  // namespace

ControlServer::ControlServer(std::filesystem::path path, Handler handler)
    : path_(std::move(path)), handler_(std::move(handler)) {
  const sockaddr_un addr = Address(path_);
  // A live server on the path answers a connect; a stale file from a killed process does not.
  {
    const int probe = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (probe >= 0) {
      const bool live = connect(probe, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) == 0;
      close(probe);
      if (live) {
        throw std::runtime_error(
            fmt::format("control socket {} is served by another process", path_.string()));
      }
    }
  }
  std::error_code ec;
  std::filesystem::remove(path_, ec);
  listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (listen_fd_ < 0) {
    throw std::runtime_error(
        fmt::format("control socket {}: socket: {}", path_.string(), std::strerror(errno)));
  }
  if (bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 ||
      listen(listen_fd_, 16) != 0) {
    const int err = errno;
    close(listen_fd_);
    throw std::runtime_error(
        fmt::format("control socket {}: cannot listen: {}", path_.string(), std::strerror(err)));
  }
}

ControlServer::~ControlServer() {
  for (Client& c : clients_) close(c.fd);
  close(listen_fd_);
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

void ControlServer::Accept() {
  for (;;) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd < 0) return;  // EAGAIN: none pending; other errors: try again next poll
    Client c;
    c.fd = fd;
    clients_.push_back(std::move(c));
  }
}

int ControlServer::Read(Client& c) {
  char buf[4096];
  for (;;) {
    const ssize_t n = recv(c.fd, buf, sizeof(buf), 0);
    if (n > 0) {
      c.in.append(buf, static_cast<size_t>(n));
      continue;
    }
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) c.closed = true;
    break;
  }
  int answered = 0;
  size_t start = 0;
  for (;;) {
    const size_t nl = c.in.find('\n', start);
    if (nl == std::string::npos) break;
    std::string_view line(c.in.data() + start, nl - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (c.skipping) {
      c.skipping = false;  // the end of an over-long line: already answered
    } else if (line.size() > kMaxControlLineBytes) {
      c.out += EncodeControlReply(ControlReply::Fail(
          fmt::format("request of {} bytes exceeds {} bytes", line.size(), kMaxControlLineBytes)));
      ++answered;
    } else {
      c.out += EncodeControlReply(handler_(line));
      ++answered;
    }
    start = nl + 1;
  }
  c.in.erase(0, start);
  if (!c.skipping && c.in.size() > kMaxControlLineBytes) {
    c.out += EncodeControlReply(
        ControlReply::Fail(fmt::format("request exceeds {} bytes", kMaxControlLineBytes)));
    ++answered;
    c.in.clear();
    c.skipping = true;
  } else if (c.skipping) {
    c.in.clear();
  }
  return answered;
}

void ControlServer::Flush(Client& c) {
  while (!c.out.empty()) {
    const ssize_t n = send(c.fd, c.out.data(), c.out.size(), MSG_NOSIGNAL);
    if (n > 0) {
      c.out.erase(0, static_cast<size_t>(n));
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    c.out.clear();  // the peer is gone
    c.closed = true;
    return;
  }
}

void ControlServer::AddPollFds(std::vector<pollfd>& fds) const {
  fds.push_back({listen_fd_, POLLIN, 0});
  for (const Client& c : clients_) {
    fds.push_back({c.fd, static_cast<short>(POLLIN | (c.out.empty() ? 0 : POLLOUT)), 0});
  }
}

int ControlServer::Poll(int timeout_ms) {
  std::vector<pollfd> fds;
  fds.push_back({listen_fd_, POLLIN, 0});
  for (const Client& c : clients_) {
    fds.push_back({c.fd, static_cast<short>(POLLIN | (c.out.empty() ? 0 : POLLOUT)), 0});
  }
  if (poll(fds.data(), fds.size(), timeout_ms < 0 ? 0 : timeout_ms) <= 0) return 0;
  int answered = 0;
  for (size_t i = 0; i < clients_.size(); ++i) {
    const short ev = fds[i + 1].revents;
    if ((ev & (POLLIN | POLLHUP | POLLERR)) != 0) answered += Read(clients_[i]);
    Flush(clients_[i]);
  }
  if ((fds[0].revents & POLLIN) != 0) {
    const size_t before = clients_.size();
    Accept();
    // Requests often arrive with the connection: answer them in this call.
    for (size_t i = before; i < clients_.size(); ++i) {
      answered += Read(clients_[i]);
      Flush(clients_[i]);
    }
  }
  std::erase_if(clients_, [](const Client& c) {
    if (c.closed && c.out.empty()) {
      close(c.fd);
      return true;
    }
    return false;
  });
  return answered;
}

}  // namespace dt
