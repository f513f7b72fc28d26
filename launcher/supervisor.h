// Supervisor: named child processes, their prefixed output, READY detection and clean stops.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/result.h"
#include "launcher/child_process.h"

namespace dt {

// Runs named children (each may be restarted under the same name). Every output line is handed
// to the sink with the child's name. A child counts as ready once it prints "READY <name>" after
// its latest start (docs/launcher.md). Of each start it remembers the latest line about clock
// skew (log::kClockSkewMarker) or another ground (log::kGroundMismatchMarker) and the latest
// warning or error line, so a child that never becomes ready can be reported with why it said it
// could not. Single-threaded: Poll() does the reading and reaping.
class Supervisor {
 public:
  using LineSink = std::function<void(const std::string& name, std::string_view line)>;

  // Writes "[name] line" to stdout, flushing each line.
  static void PrintPrefixed(const std::string& name, std::string_view line);

  explicit Supervisor(LineSink sink = PrintPrefixed);
  ~Supervisor();  // children still running are killed by PID and reaped

  // Starts (or restarts, once the previous one has exited) a child. Throws std::runtime_error
  // if it cannot start or the name is running, naming both.
  void Start(const std::string& name, const std::vector<std::string>& argv);

  // A file descriptor that ends Poll's wait when readable (a signal's self-pipe); -1: none.
  void set_wake_fd(int fd) { wake_fd_ = fd; }

  // Waits up to timeout_ms for output, exits or the wake fd; handles what arrived. Returns true
  // if the wake fd became readable (it is not drained).
  bool Poll(int timeout_ms);

  // Polls until every named child is ready. An Error names the child that exited first (with
  // how), or those not ready when timeout_ms ran out, each with its last_word (if any), or the
  // wake fd that interrupted.
  Status WaitReady(const std::vector<std::string>& names, int timeout_ms);
  // Polls until the child has exited; false on timeout or wake.
  bool WaitExit(const std::string& name, int timeout_ms);

  // Signals one child's process group (no-op if it is not running).
  void Signal(const std::string& name, int signal_number);
  // SIGTERM to every running child's group, then SIGKILL to those still running after grace_ms,
  // or at once if the wake fd becomes readable again (a second Ctrl-C). Drains the wake fd.
  void StopAll(int grace_ms);

  bool running(const std::string& name) const;
  bool ready(const std::string& name) const;
  // The wait status of the child's last run (see DescribeWaitStatus); -1 if it never exited.
  int last_wait_status(const std::string& name) const;
  // The latest line of the child's current start about clock skew or another ground, else its
  // latest warning or error line (spdlog's " warning [", " error [", " critical ["), else empty.
  std::string last_word(const std::string& name) const;
  std::vector<std::string> names() const;  // every child ever started, in start order
  bool any_running() const;

 private:
  struct Entry {
    std::unique_ptr<ChildProcess> process;
    bool ready = false;
    int last_wait_status = -1;
    std::string last_clock_line;    // of this start
    std::string last_warning_line;  // of this start
  };
  void Drain(const std::string& name, Entry& e);
  // Hands a line to the sink and keeps it if it is one for last_word.
  void Take(const std::string& name, Entry& e, std::string_view line);
  // Reaps a child that has exited, handing its last lines to the sink; true if it exited.
  bool ReapIfDone(const std::string& name, Entry& e);

  LineSink sink_;
  int wake_fd_ = -1;
  std::map<std::string, Entry> children_;
  std::vector<std::string> order_;
};

}  // namespace dt
