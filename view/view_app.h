// ViewApp: the live view process (docs/view.md): an observer process of the exercise with the
// page's model, the process poller and the web server.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include "runtime/exercise_config.h"
#include "runtime/observer_process.h"
#include "view/loop_requests.h"
#include "view/process_poller.h"
#include "view/relief_tiles.h"
#include "view/shared_vehicle_source.h"
#include "view/view_model.h"
#include "view/web_server.h"

namespace dt {

struct ViewOptions {
  std::filesystem::path web_dir;  // the page's files (view/web)
  bool allow_commands = false;    // operator actions from the page (off unless asked)
  int poll_period_ms = 100;       // each process's status
};

class ViewApp : public ObserverProcess {
 public:
  // Throws std::invalid_argument when the exercise has no [view] named `name`, and
  // std::runtime_error when the page's address cannot be listened on.
  ViewApp(const ExerciseConfig& exercise, const std::string& name, ViewOptions options);
  ~ViewApp() override;

  std::string url() const;

 private:
  // The protocol's tick is done: the pages' delta, the relief tiles a change touched, and the
  // posts of the tiles pages asked for.
  void OnTick(int64_t now_ms) override;
  std::string RefusalText() const override;
  std::string ReadyLines() const override { return "VIEW " + url(); }
  std::string StopSummary() const override;
  std::string OnMessage(const std::string& text);

  const ViewConfig& view_;
  ViewOptions options_;
  std::unique_ptr<ViewModel> model_;
  std::unique_ptr<ProcessPoller> poller_;
  std::unique_ptr<SharedVehicleSource> vehicles_;
  // The 3D view's terrain windows: asked on the web server's threads, built on the loop. Before
  // web_, so the server's threads stop before it goes.
  LoopRequests windows_;
  static constexpr int kWindowTimeoutMs = 2000;
  static constexpr size_t kWindowsPerTick = 2;  // each is a few ms at 129^2 samples
  // The relief's tiles (docs/view.md "The relief"): asked on the web server's threads, sampled on
  // the loop, drawn on their own thread. Before web_, like windows_.
  std::unique_ptr<ReliefTiles> relief_;
  static constexpr int kTileTimeoutMs = 5000;
  static constexpr size_t kTilesPerTick = 4;  // each reads 257^2 to 513^2 posts and squares
  std::unique_ptr<WebServer> web_;
  std::set<std::string> nodes_;
  // The version of tile 0/0/0 (the whole world), as the delta's "relief" for /relief.png.
  int relief_version_ = 0;
};

}  // namespace dt
