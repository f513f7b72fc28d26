// dt_node: one node of an exercise: a fixed-rate loop over its replica, vehicles, scenario and
// control socket. Prints "READY <name>" once signed on and caught up.
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "log/log.h"
#include "node/node_app.h"
#include "runtime/control_server.h"
#include "runtime/exercise_flags.h"
#include "runtime/process_runtime.h"

int main(int argc, char** argv) {
  CLI::App app{"A dynterrain node"};
  dt::ExerciseFlags flags;
  std::string name;
  std::string level = "info";
  flags.AddTo(app);
  app.add_option("--name", name, "this node's name in the exercise")->required();
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    dt::log::Init(name, level);
    dt::ExerciseConfig exercise = flags.Load();
    const dt::ProcessConfig* process = exercise.FindProcess(name);
    if (process == nullptr || (exercise.server && process == &*exercise.server) ||
        (exercise.standby && process == &*exercise.standby) ||
        (exercise.view && process == &exercise.view->process)) {
      throw std::invalid_argument(
          fmt::format("{}: no [[node]] named \"{}\"", exercise.source.string(), name));
    }
    dt::InstallStopSignals();
    // Before the node: its feature number reservation lives there.
    std::filesystem::create_directories(exercise.run_dir);
    dt::NodeApp node(exercise, *process);
    dt::ControlServer control(exercise.SocketPath(name),
                              [&](std::string_view line) { return node.Handle(line); });

    const int64_t tick_ms = 1000 / exercise.tick_hz;
    int64_t next_ms = dt::MonotonicMs();
    node.Start(next_ms);
    while (!dt::StopRequested() && !node.quit_requested()) {
      const int64_t now = dt::MonotonicMs();
      node.Tick(now, static_cast<double>(tick_ms) / 1000.0);
      control.Poll(0);
      next_ms += tick_ms;
      // Behind by more than a tick (a long catch-up): start afresh rather than spin.
      if (next_ms < dt::MonotonicMs() - tick_ms) next_ms = dt::MonotonicMs();
      // Receive until the next tick is due.
      // Until the next tick: PDUs and control requests as they arrive.
      for (int64_t left; (left = next_ms - dt::MonotonicMs()) > 0 && !dt::StopRequested() &&
                         !node.quit_requested();) {
        dt::WaitForWork(node.transport_fd(), node.needs_handling(), control,
                        static_cast<int>(left));
        node.Receive(0);
        control.Poll(0);
      }
      node.Receive(0);  // at least once per tick, even when behind
    }
    const auto c = node.replica().counters();
    DT_LOG_INFO("stopping: {} features, digest {}, sent {}, received {}, rejected {}",
                node.replica().live_feature_count(), node.replica().Digest(), c.sent, c.received,
                c.rejected);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_node %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}
