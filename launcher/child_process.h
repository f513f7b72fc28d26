// ChildProcess: one spawned program whose stdout and stderr arrive as lines on a pipe.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dt {

// Describes how a child ended, e.g. "exited 0", "killed by signal 9 (Killed)".
std::string DescribeWaitStatus(int wait_status);

// Spawns argv[0] (searched on PATH) in its own process group, so a terminal's Ctrl-C reaches
// only the parent, which stops children itself, by PID. Both output streams go to one pipe.
class ChildProcess {
 public:
  // Throws std::runtime_error naming the program if it cannot be started (exec failure is
  // detected here, not later as an odd exit code). Throws std::invalid_argument for empty argv.
  explicit ChildProcess(const std::vector<std::string>& argv);
  ~ChildProcess();  // a still-running child is killed (SIGKILL) and reaped: no orphans
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  int output_fd() const { return out_fd_; }  // -1 once the child closed its end and it drained

  // Reads what is available (non-blocking) and returns the complete lines; a partial last line
  // is kept until its newline or end of output.
  std::vector<std::string> ReadLines();

  // Non-blocking reap; returns true once the child has exited (then wait_status() is set).
  bool Reap();
  bool exited() const { return wait_status_.has_value(); }
  int wait_status() const { return wait_status_.value_or(0); }

  // Sends a signal to the child's PID (not its group); no-op once reaped.
  void Signal(int signal_number) const;

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string partial_;
  std::optional<int> wait_status_;
};

}  // namespace dt
