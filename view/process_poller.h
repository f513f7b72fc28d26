// ProcessPoller: asks every process of the exercise file for its `status` on its control socket,
// on a thread of its own so a stopped process never holds the view's loop (docs/view.md).
#pragma once

#include <atomic>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "view/process_row.h"

namespace dt {

struct PolledProcess {
  std::string name, role, address;
  std::filesystem::path socket;
};

// The rows' control-socket fields (vehicles come by PDU: view/shared_vehicle_source.h).
class ProcessPoller {
 public:
  // Polls each process every period_ms, waiting at most timeout_ms for a reply.
  ProcessPoller(std::vector<PolledProcess> processes, int period_ms, int timeout_ms);
  ~ProcessPoller();
  ProcessPoller(const ProcessPoller&) = delete;
  ProcessPoller& operator=(const ProcessPoller&) = delete;

  std::vector<ProcessRow> Rows() const;

 private:
  void Run();

  std::vector<PolledProcess> processes_;
  int period_ms_, timeout_ms_;
  mutable std::mutex mu_;
  std::vector<ProcessRow> rows_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace dt
