#include "view/process_poller.h"

#include <chrono>
#include <sstream>

#include "runtime/control_client.h"

namespace dt {

std::vector<VehicleView> ParseStatusVehicles(const std::string& status_text,
                                             const std::string& owner) {
  std::vector<VehicleView> out;
  std::istringstream in(status_text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("vehicle ", 0) != 0) continue;
    std::istringstream words(line);
    std::string tag, index, word;
    VehicleView v;
    v.owner = owner;
    words >> tag >> index >> v.type;
    v.id = owner + "/" + index;
    while (words >> word) {
      const size_t eq = word.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
      try {
        if (key == "x_m") v.x_m = std::stod(value);
        if (key == "z_m") v.z_m = std::stod(value);
        if (key == "heading_rad") v.heading_rad = std::stod(value);
        if (key == "speed_mps") v.speed_mps = std::stod(value);
        if (key == "alive") v.alive = value == "1";
      } catch (const std::exception&) {
        // A value that is no number leaves the field as it was: the page shows what parsed.
      }
    }
    out.push_back(v);
  }
  return out;
}

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

std::vector<VehicleView> ProcessPoller::Vehicles() {
  std::lock_guard lock(mu_);
  return vehicles_;
}

void ProcessPoller::Run() {
  while (!stop_) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<ProcessRow> rows;
    std::vector<VehicleView> vehicles;
    for (const PolledProcess& p : processes_) {
      ProcessRow r;
      r.name = p.name;
      r.role = p.role;
      r.address = p.address;
      auto reply = CallControl(p.socket, "status", timeout_ms_);
      if (reply && reply.value().ok) {
        r.reachable = true;
        ParseStatusInto(reply.value().body, r);
        auto vs = ParseStatusVehicles(reply.value().body, p.name);
        vehicles.insert(vehicles.end(), vs.begin(), vs.end());
      }
      rows.push_back(std::move(r));
    }
    {
      std::lock_guard lock(mu_);
      rows_ = std::move(rows);
      vehicles_ = std::move(vehicles);
    }
    const auto next = start + std::chrono::milliseconds(period_ms_);
    while (!stop_ && std::chrono::steady_clock::now() < next) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));  // pacing, not synchronisation
    }
  }
}

}  // namespace dt
