#include "runtime/control_client.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include <fmt/format.h>

namespace dt {
namespace {

// Closes the descriptor on every path out.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) close(fd);
  }
};

Result<ControlReply> ParseReply(const std::string& text) {
  ControlReply reply;
  size_t nl = text.find('\n');
  const std::string status = text.substr(0, nl);
  if (status == "ok") {
    reply.ok = true;
  } else if (status.rfind("error: ", 0) == 0) {
    reply.ok = false;
    reply.error = status.substr(7);
  } else {
    return Error{fmt::format("malformed reply status line \"{}\"", status)};
  }
  std::string body;
  size_t start = nl + 1;
  for (;;) {
    const size_t end = text.find('\n', start);
    std::string_view line(text.data() + start, end - start);
    if (line == ".") break;
    if (line == "..") line = ".";
    if (!body.empty()) body += '\n';
    body += line;
    start = end + 1;
  }
  reply.body = std::move(body);
  return reply;
}

}  // namespace

Result<ControlReply> CallControl(const std::filesystem::path& socket_path, std::string_view line,
                                 int timeout_ms) {
  const std::string where = socket_path.string();
  if (line.find('\n') != std::string_view::npos) {
    return Error{fmt::format("{}: a request is one line", where)};
  }
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (where.empty() || where.size() >= sizeof(addr.sun_path)) {
    return Error{fmt::format("{}: path too long for a Unix socket ({} bytes, at most {})", where,
                             where.size(), sizeof(addr.sun_path) - 1)};
  }
  std::memcpy(addr.sun_path, where.data(), where.size());
  Fd s{socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0)};
  if (s.fd < 0) return Error{fmt::format("{}: socket: {}", where, std::strerror(errno))};
  if (connect(s.fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    return Error{fmt::format("{}: cannot connect: {}", where, std::strerror(errno))};
  }
  std::string request(line);
  request += '\n';
  size_t sent = 0;
  while (sent < request.size()) {
    const ssize_t n = send(s.fd, request.data() + sent, request.size() - sent, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      return Error{fmt::format("{}: send: {}", where, std::strerror(errno))};
    }
    sent += static_cast<size_t>(n);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  std::string text;
  char buf[4096];
  for (;;) {
    // Body lines are never a lone "." (the server escapes them), so this is the end.
    if (text.size() >= 3 && text.compare(text.size() - 3, 3, "\n.\n") == 0) {
      return ParseReply(text);
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      return Error{fmt::format("{}: no reply to \"{}\" within {} ms", where, line, timeout_ms)};
    }
    pollfd p{s.fd, POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(left.count()));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    const ssize_t n = recv(s.fd, buf, sizeof(buf), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Error{
          fmt::format("{}: connection closed before the reply to \"{}\" ended", where, line)};
    }
    text.append(buf, static_cast<size_t>(n));
  }
}

}  // namespace dt
