#include "launcher/supervisor.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "log/log.h"

namespace dt {
namespace {

using Clock = std::chrono::steady_clock;

int MsLeft(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left < 0 ? 0 : static_cast<int>(left);
}

// A child's exit does not always end its output (a descendant may hold the pipe) and its output
// may end long before it exits: while any child runs, Poll waits at most this long between
// reaping attempts.
constexpr int kReapCheckMs = 100;

// Reads everything in the (non-blocking) wake pipe; true if there was anything.
bool DrainWakeFd(int fd) {
  if (fd < 0) return false;
  bool any = false;
  char buf[64];
  for (;;) {
    const ssize_t n = read(fd, buf, sizeof(buf));
    if (n > 0) {
      any = true;
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    return any;
  }
}

// A line kept for last_word is cut to this: it is quoted in one error message.
constexpr size_t kMaxKeptLineBytes = 600;

// Whether a line is a log line (log/log.h's pattern) of level warning or above.
bool IsWarning(std::string_view line) {
  for (std::string_view level : {" warning [", " error [", " critical ["}) {
    if (line.find(level) != std::string_view::npos) return true;
  }
  return false;
}

}  // namespace

void Supervisor::PrintPrefixed(const std::string& name, std::string_view line) {
  std::fwrite("[", 1, 1, stdout);
  std::fwrite(name.data(), 1, name.size(), stdout);
  std::fwrite("] ", 1, 2, stdout);
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fwrite("\n", 1, 1, stdout);
  std::fflush(stdout);
}

Supervisor::Supervisor(LineSink sink) : sink_(std::move(sink)) {}

Supervisor::~Supervisor() {
  for (auto& [name, e] : children_) e.process.reset();
}

void Supervisor::Start(const std::string& name, const std::vector<std::string>& argv) {
  auto it = children_.find(name);
  if (it != children_.end() && it->second.process && !it->second.process->exited()) {
    throw std::runtime_error(
        fmt::format("{} is already running (pid {})", name, it->second.process->pid()));
  }
  Entry& e = children_[name];
  if (it == children_.end()) order_.push_back(name);
  e.process.reset();
  e.ready = false;
  e.last_clock_line.clear();
  e.last_warning_line.clear();
  try {
    e.process = std::make_unique<ChildProcess>(argv);
  } catch (const std::exception& ex) {
    throw std::runtime_error(fmt::format("{}: {}", name, ex.what()));
  }
}

void Supervisor::Take(const std::string& name, Entry& e, std::string_view line) {
  if (line.find(log::kClockSkewMarker) != std::string_view::npos ||
      line.find(log::kGroundMismatchMarker) != std::string_view::npos) {
    e.last_clock_line = line.substr(0, kMaxKeptLineBytes);
  } else if (IsWarning(line)) {
    e.last_warning_line = line.substr(0, kMaxKeptLineBytes);
  }
  sink_(name, line);
}

void Supervisor::Drain(const std::string& name, Entry& e) {
  for (std::string& line : e.process->ReadLines()) {
    if (line == "READY " + name) e.ready = true;
    Take(name, e, line);
  }
}

bool Supervisor::ReapIfDone(const std::string& name, Entry& e) {
  if (e.process->exited()) return true;
  if (!e.process->Reap()) return false;
  for (std::string& line : e.process->FinishOutput()) Take(name, e, line);
  e.ready = false;
  e.last_wait_status = e.process->wait_status();
  return true;
}

bool Supervisor::Poll(int timeout_ms) {
  std::vector<pollfd> fds;
  std::vector<std::pair<const std::string*, Entry*>> owners;
  bool any_live = false;
  for (auto& [name, e] : children_) {
    if (!e.process) continue;
    if (e.process->output_fd() >= 0) {
      fds.push_back({e.process->output_fd(), POLLIN, 0});
      owners.emplace_back(&name, &e);
    }
    any_live |= !e.process->exited();
  }
  if (wake_fd_ >= 0) fds.push_back({wake_fd_, POLLIN, 0});
  const int wait_ms = any_live && timeout_ms > kReapCheckMs ? kReapCheckMs : timeout_ms;
  const int r = poll(fds.data(), fds.size(), wait_ms);
  bool woken = false;
  if (r > 0) {
    for (size_t i = 0; i < owners.size(); ++i) {
      if (fds[i].revents != 0) Drain(*owners[i].first, *owners[i].second);
    }
    woken = wake_fd_ >= 0 && (fds.back().revents & POLLIN) != 0;
  }
  // A dead child's last lines are still in the pipe when it is reaped: ReapIfDone reads them.
  for (auto& [name, e] : children_) {
    if (e.process) ReapIfDone(name, e);
  }
  return woken;
}

Status Supervisor::WaitReady(const std::vector<std::string>& wanted, int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    std::vector<std::string> missing;
    for (const std::string& n : wanted) {
      auto it = children_.find(n);
      if (it == children_.end() || !it->second.process) {
        return Error{fmt::format("{} was never started", n)};
      }
      const Entry& e = it->second;
      if (e.process->exited()) {
        return Error{fmt::format("{} {} before it was ready", n,
                                 DescribeWaitStatus(e.process->wait_status()))};
      }
      if (!e.ready) missing.push_back(n);
    }
    if (missing.empty()) return Status::Ok();
    const int left = MsLeft(deadline);
    if (left == 0) {
      // What a child said last about why is the answer its bare name does not give (a clock 45 s
      // off is otherwise nothing but "not ready").
      for (std::string& n : missing) {
        if (const std::string word = last_word(n); !word.empty()) {
          n = fmt::format("{} (its last word: \"{}\")", n, word);
        }
      }
      return Error{fmt::format("not ready after {} ms: {}", timeout_ms, fmt::join(missing, ", "))};
    }
    if (Poll(left)) return Error{"interrupted while waiting for READY"};
  }
}

bool Supervisor::WaitExit(const std::string& name, int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    auto it = children_.find(name);
    if (it == children_.end() || !it->second.process || it->second.process->exited()) return true;
    const int left = MsLeft(deadline);
    if (left == 0) return false;
    if (Poll(left)) return false;
  }
}

void Supervisor::Signal(const std::string& name, int signal_number) {
  auto it = children_.find(name);
  if (it != children_.end() && it->second.process) it->second.process->Signal(signal_number);
}

void Supervisor::StopAll(int grace_ms) {
  // The stop signal that brought us here (if any) is used up; another one, from here on, asks
  // to stop at once. Left in the pipe, it would end every Poll below at once: a busy loop.
  DrainWakeFd(wake_fd_);
  for (auto& [name, e] : children_) {
    if (e.process) e.process->Signal(SIGTERM);
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(grace_ms);
  bool signalled_again = false;
  while (any_running() && MsLeft(deadline) > 0 && !signalled_again) {
    signalled_again = Poll(MsLeft(deadline)) && DrainWakeFd(wake_fd_);
  }
  for (auto& [name, e] : children_) {
    if (e.process && !e.process->exited()) {
      e.process->Signal(SIGKILL);
      sink_(name, signalled_again
                      ? std::string("(another stop signal during the stop: sent SIGKILL)")
                      : fmt::format("(still running {} ms after SIGTERM: sent SIGKILL)", grace_ms));
    }
  }
  while (any_running()) {
    if (Poll(kReapCheckMs)) DrainWakeFd(wake_fd_);
  }
}

bool Supervisor::running(const std::string& name) const {
  auto it = children_.find(name);
  return it != children_.end() && it->second.process && !it->second.process->exited();
}

bool Supervisor::ready(const std::string& name) const {
  auto it = children_.find(name);
  return it != children_.end() && it->second.ready;
}

int Supervisor::last_wait_status(const std::string& name) const {
  auto it = children_.find(name);
  return it == children_.end() ? -1 : it->second.last_wait_status;
}

std::string Supervisor::last_word(const std::string& name) const {
  auto it = children_.find(name);
  if (it == children_.end()) return {};
  const Entry& e = it->second;
  return e.last_clock_line.empty() ? e.last_warning_line : e.last_clock_line;
}

std::vector<std::string> Supervisor::names() const { return order_; }

bool Supervisor::any_running() const {
  for (const auto& [name, e] : children_) {
    if (e.process && !e.process->exited()) return true;
  }
  return false;
}

}  // namespace dt
