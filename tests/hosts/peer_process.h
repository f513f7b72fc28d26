// PeerProcess: hosts_bench's handle on one peer it started (tests/hosts/bench_peer.h): its PID,
// the pipes of its commands and answers, waits bounded in time.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dt::hostsbench {

// An answer: the steady-clock time it carries and the values after it.
struct Answer {
  int64_t t_ns = 0;
  std::vector<std::string> values;
};

class PeerProcess {
 public:
  // Starts argv with its stdin and stdout on pipes (stderr stays the bench's) and waits up to
  // timeout_ms for its `0 ok <ns>` line: `started_ns()`. Throws std::runtime_error naming `name`
  // if it cannot start or does not answer in time.
  PeerProcess(std::string name, const std::vector<std::string>& argv, int timeout_ms);
  ~PeerProcess();  // SIGKILLs it if it still runs, and reaps it
  PeerProcess(const PeerProcess&) = delete;
  PeerProcess& operator=(const PeerProcess&) = delete;

  // Sends `<id> <command>`; returns the id.
  int Send(const std::string& command);
  // Waits up to timeout_ms for the answer to `id`. Throws std::runtime_error naming the peer, the
  // command and what it said on an error answer, on a timeout, or if the peer has ended.
  Answer Wait(int id, int timeout_ms);
  // True (and `out` set) if the answer to `id` has come; reads what is waiting, never blocks.
  bool Poll(int id, Answer& out);
  // Send then Wait.
  Answer Ask(const std::string& command, int timeout_ms) { return Wait(Send(command), timeout_ms); }

  // SIGKILL, as a crash; reaps it.
  void Kill();
  int64_t started_ns() const { return started_ns_; }
  const std::string& name() const { return name_; }
  int out_fd() const { return out_fd_; }

 private:
  void ReadAvailable();

  std::string name_;
  pid_t pid_ = -1;
  int in_fd_ = -1;   // its stdin
  int out_fd_ = -1;  // its stdout
  int next_id_ = 1;
  int64_t started_ns_ = 0;
  std::string partial_;
  std::map<int, std::string> answers_;  // id -> the rest of its line
  std::map<int, std::string> sent_;     // id -> command, for messages
};

// Waits up to timeout_ms for the first answer among (peer, id) pairs; returns its index and
// answer. Throws std::runtime_error on a timeout.
std::pair<size_t, Answer> WaitFirst(const std::vector<std::pair<PeerProcess*, int>>& waits,
                                    int timeout_ms);

}  // namespace dt::hostsbench
