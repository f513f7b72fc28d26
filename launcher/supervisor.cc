#include "launcher/supervisor.h"

#include <poll.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace dt {
namespace {

using Clock = std::chrono::steady_clock;

int MsLeft(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left < 0 ? 0 : static_cast<int>(left);
}

// A child's exit is noticed when its output ends, but a child may close its output and live on;
// this bounds how long Poll waits before reaping such children.
constexpr int kReapCheckMs = 100;

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
  try {
    e.process = std::make_unique<ChildProcess>(argv);
  } catch (const std::exception& ex) {
    throw std::runtime_error(fmt::format("{}: {}", name, ex.what()));
  }
}

void Supervisor::Drain(const std::string& name, Entry& e) {
  for (std::string& line : e.process->ReadLines()) {
    if (line == "READY " + name) e.ready = true;
    sink_(name, line);
  }
}

bool Supervisor::ReapIfDone(Entry& e) {
  if (e.process->exited()) return true;
  if (e.process->Reap()) {
    e.ready = false;
    e.last_wait_status = e.process->wait_status();
    return true;
  }
  return false;
}

bool Supervisor::Poll(int timeout_ms) {
  std::vector<pollfd> fds;
  std::vector<std::pair<const std::string*, Entry*>> owners;
  bool live_without_output = false;
  for (auto& [name, e] : children_) {
    if (!e.process) continue;
    if (e.process->output_fd() >= 0) {
      fds.push_back({e.process->output_fd(), POLLIN, 0});
      owners.emplace_back(&name, &e);
    } else if (!e.process->exited()) {
      live_without_output = true;
    }
  }
  if (wake_fd_ >= 0) fds.push_back({wake_fd_, POLLIN, 0});
  const int wait_ms = live_without_output && timeout_ms > kReapCheckMs ? kReapCheckMs : timeout_ms;
  const int r = poll(fds.data(), fds.size(), wait_ms);
  bool woken = false;
  if (r > 0) {
    for (size_t i = 0; i < owners.size(); ++i) {
      if (fds[i].revents != 0) Drain(*owners[i].first, *owners[i].second);
    }
    woken = wake_fd_ >= 0 && (fds.back().revents & POLLIN) != 0;
  }
  for (auto& [name, e] : children_) {
    // Reap only after the output has ended, so no line of a dead child is lost.
    if (e.process && e.process->output_fd() < 0) ReapIfDone(e);
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
  for (auto& [name, e] : children_) {
    if (e.process) e.process->Signal(SIGTERM);
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(grace_ms);
  while (any_running() && MsLeft(deadline) > 0) Poll(MsLeft(deadline));
  for (auto& [name, e] : children_) {
    if (e.process && !e.process->exited()) {
      e.process->Signal(SIGKILL);
      sink_(name, fmt::format("(still running {} ms after SIGTERM: sent SIGKILL)", grace_ms));
    }
  }
  while (any_running()) Poll(kReapCheckMs);
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

std::vector<std::string> Supervisor::names() const { return order_; }

bool Supervisor::any_running() const {
  for (const auto& [name, e] : children_) {
    if (e.process && !e.process->exited()) return true;
  }
  return false;
}

}  // namespace dt
