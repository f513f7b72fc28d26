#include "view/process_poller.h"

#include <chrono>
#include <map>

#include "log/log.h"
#include "runtime/control_client.h"

namespace dt {

ProcessPoller::ProcessPoller(std::vector<PolledProcess> processes, int period_ms, int timeout_ms)
    : processes_(std::move(processes)), period_ms_(period_ms), timeout_ms_(timeout_ms) {
  for (const PolledProcess& p : processes_) {
    ProcessRow r;
    r.name = p.name;
    r.role = p.role;
    r.address = p.address;
    rows_.push_back(r);
  }
  thread_ = std::thread([this] { Run(); });
}

ProcessPoller::~ProcessPoller() {
  stop_ = true;
  thread_.join();
}

std::vector<ProcessRow> ProcessPoller::Rows() const {
  std::lock_guard lock(mu_);
  return rows_;
}

void ProcessPoller::Run() {
  // Per process, why its last reply did not read: each new reason is logged once, not each poll.
  std::map<std::string, std::string> unreadable;
  while (!stop_) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<ProcessRow> rows;
    for (const PolledProcess& p : processes_) {
      ProcessRow r;
      r.name = p.name;
      r.role = p.role;
      r.address = p.address;
      auto reply = CallControl(p.socket, "status", timeout_ms_);
      if (reply && reply.value().ok) {
        r.reachable = true;
        const Status read = ParseStatusInto(reply.value().body, r);
        const std::string why = read ? "" : read.error().message;
        if (!why.empty() && why != unreadable[p.name]) {
          DT_LOG_WARN("{}: status left out of the panel: {}", p.name, why);
        }
        unreadable[p.name] = why;
      }
      rows.push_back(std::move(r));
    }
    {
      std::lock_guard lock(mu_);
      rows_ = std::move(rows);
    }
    const auto next = start + std::chrono::milliseconds(period_ms_);
    while (!stop_ && std::chrono::steady_clock::now() < next) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));  // pacing, not synchronisation
    }
  }
}

}  // namespace dt
