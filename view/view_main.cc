// dt_view: the live operator view (docs/view.md): an observer replica of the exercise that
// serves a web page and pushes every change to it over a WebSocket.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "log/log.h"
#include "runtime/control_server.h"
#include "runtime/exercise_flags.h"
#include "runtime/process_runtime.h"
#include "view/view_app.h"

int main(int argc, char** argv) {
  CLI::App app{"The dynterrain live view: a web page of the exercise as it happens"};
  dt::ExerciseFlags flags;
  std::string name = "view";
  std::string level = "info";
  dt::ViewOptions options;
  options.web_dir = DT_VIEW_WEB_DIR;
  std::string web_dir = options.web_dir.string();
  flags.AddTo(app);
  app.add_option("--name", name, "the view's name in the exercise ([view])")->capture_default_str();
  app.add_flag("--allow-commands", options.allow_commands,
               "let the page place and destroy features through the nodes' control sockets");
  app.add_option("--web-dir", web_dir, "the page's files")->capture_default_str();
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  options.web_dir = web_dir;

  try {
    dt::log::Init(name, level);
    dt::ExerciseConfig exercise = flags.Load();
    dt::InstallStopSignals();
    std::filesystem::create_directories(exercise.run_dir);
    dt::ViewApp view(exercise, name, options);
    dt::ControlServer control(exercise.SocketPath(name),
                              [&](std::string_view line) { return view.Handle(line); });
    const int64_t tick_ms = 1000 / exercise.tick_hz;
    int64_t next_ms = dt::MonotonicMs();
    view.Start(next_ms);
    std::printf("VIEW %s\nREADY %s\n", view.url().c_str(), name.c_str());
    std::fflush(stdout);
    while (!dt::StopRequested() && !view.quit_requested()) {
      view.Tick(dt::MonotonicMs());
      control.Poll(0);
      next_ms += tick_ms;
      if (next_ms < dt::MonotonicMs() - tick_ms) next_ms = dt::MonotonicMs();
      for (int64_t left; (left = next_ms - dt::MonotonicMs()) > 0 && !dt::StopRequested() &&
                         !view.quit_requested();) {
        dt::WaitForWork(view.transport_fd(), view.needs_handling(), control,
                        static_cast<int>(left));
        view.Receive(0);
        control.Poll(0);
      }
      view.Receive(0);
    }
    DT_LOG_INFO("stopping: {} features, digest {}", view.replica().live_feature_count(),
                view.replica().Digest());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_view %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}
