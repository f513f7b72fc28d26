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
// only the parent, which stops children itself. Both output streams go to one pipe. Signals go
// to the child's whole group: a child started through a wrapper that forks (faketime, a shell)
// is stopped with everything it started.
class ChildProcess {
 public:
  // Throws std::runtime_error naming the program if it cannot be started (exec failure is
  // detected here, not later as an odd exit code). Throws std::invalid_argument for empty argv.
  explicit ChildProcess(const std::vector<std::string>& argv);
  ~ChildProcess();  // a still-running child's group is killed (SIGKILL), the child reaped
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  int output_fd() const { return out_fd_; }  // -1 once the child closed its end and it drained

  // Reads what is available (non-blocking) and returns the complete lines; a partial last line
  // is kept until its newline or end of output.
  std::vector<std::string> ReadLines();

  // Non-blocking reap; returns true once the child has exited (then wait_status() is set).
  // On the exit, what the child left in the pipe stays readable with ReadLines.
  bool Reap();
  bool exited() const { return wait_status_.has_value(); }
  int wait_status() const { return wait_status_.value_or(0); }

  // Sends a signal to the child's process group; no-op once reaped.
  void Signal(int signal_number) const;

  // Once the child has exited: SIGKILLs what is left of its group (descendants that still hold
  // the output pipe), reads what is left in the pipe as lines and stops reading it, so a
  // descendant that escaped the group and keeps the pipe open cannot keep the child "running".
  // Returns the last lines; nothing once the output has ended.
  std::vector<std::string> FinishOutput();

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string partial_;
  std::optional<int> wait_status_;
};

}  // namespace dt
