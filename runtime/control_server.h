// ControlServer: the Unix-domain control socket a process serves inside its own loop.
#pragma once

#include <poll.h>

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/control_protocol.h"

namespace dt {

// Listens on a Unix-domain stream socket and answers line requests with `handler`, without
// threads: Poll() does all the work and never blocks longer than it is told. A request longer
// than kMaxControlLineBytes gets an error reply and the rest of the line is skipped.
class ControlServer {
 public:
  using Handler = std::function<ControlReply(std::string_view line)>;

  // Throws std::invalid_argument if the path is too long for a socket address, and
  // std::runtime_error if it cannot listen (the message names the path and errno), including
  // when another live process already serves the path. A stale socket file is replaced.
  ControlServer(std::filesystem::path path, Handler handler);
  ~ControlServer();  // closes every connection and removes the socket file
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  // Accepts new connections, reads what arrived, answers every complete line and writes pending
  // replies. Waits up to timeout_ms for activity when there is nothing to do. Returns the number
  // of requests answered.
  int Poll(int timeout_ms);

  // Adds the descriptors Poll would wait on (listening socket, connections; POLLOUT where a
  // reply is pending), so a process loop can wait on them together with its transport.
  void AddPollFds(std::vector<pollfd>& fds) const;

  int listen_fd() const { return listen_fd_; }
  const std::filesystem::path& path() const { return path_; }
  size_t connections() const { return clients_.size(); }

 private:
  struct Client {
    int fd = -1;
    std::string in;
    std::string out;
    bool skipping = false;  // inside an over-long line
    bool closed = false;    // peer closed; drop once `out` is flushed
  };

  void Accept();
  int Read(Client& c);
  void Flush(Client& c);

  std::filesystem::path path_;
  Handler handler_;
  int listen_fd_ = -1;
  std::vector<Client> clients_;
};

}  // namespace dt
