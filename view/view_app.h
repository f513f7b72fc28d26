// ViewApp: the live view process (docs/view.md): an observer replica of the exercise, the page's
// model, the process poller and the web server, stepped by dt_view's loop.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "engine/replica.h"
#include "runtime/control_protocol.h"
#include "runtime/exercise_config.h"
#include "runtime/process_runtime.h"
#include "view/process_poller.h"
#include "view/relief_renderer.h"
#include "view/shared_vehicle_source.h"
#include "view/view_model.h"
#include "view/web_server.h"

namespace dt {

struct ViewOptions {
  std::filesystem::path web_dir;  // the page's files (view/web)
  bool allow_commands = false;    // operator actions from the page (off unless asked)
  int poll_period_ms = 100;       // each process's status
  int relief_min_period_ms = 1000;
};

class ViewApp {
 public:
  // Throws std::invalid_argument when the exercise has no [view] named `name`, and
  // std::runtime_error when the page's address cannot be listened on.
  ViewApp(const ExerciseConfig& exercise, const std::string& name, ViewOptions options);
  ~ViewApp();

  void Start(int64_t now_ms);
  // Protocol tick, then the pages' delta (and the relief when the terrain changed).
  void Tick(int64_t now_ms);
  ControlReply Handle(std::string_view line);
  void Receive(int timeout_ms) { (void)transport_.bus->HandleTimeout(timeout_ms); }

  bool quit_requested() const { return quit_; }
  int transport_fd() const { return transport_.bus->Fd(); }
  bool needs_handling() const { return transport_.needs_handling(); }
  const Replica& replica() const { return *replica_; }
  std::string url() const;

 private:
  std::string OnMessage(const std::string& text);
  void RenderRelief(int64_t now_ms);

  const ExerciseConfig& exercise_;
  const ViewConfig& view_;
  ViewOptions options_;
  ProcessTransport transport_;
  std::unique_ptr<Replica> replica_;
  std::unique_ptr<ViewModel> model_;
  std::unique_ptr<ProcessPoller> poller_;
  std::unique_ptr<SharedVehicleSource> vehicles_;
  std::unique_ptr<WebServer> web_;
  std::unique_ptr<ReliefRenderer> relief_;
  std::set<std::string> nodes_;
  std::string relief_digest_;  // of the terrain last offered for rendering
  int relief_version_ = 0;
  int64_t relief_at_ms_ = -1;
  bool quit_ = false;
};

}  // namespace dt
