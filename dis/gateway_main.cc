// dt_dis: the DIS gateway (docs/dis.md "The gateway"): the exercise's vehicles and features as
// DIS 7 PDUs on UDP, and outside DIS entities (and, if allowed, craters) into the exercise.
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "dis/gateway_app.h"
#include "log/log.h"
#include "runtime/control_server.h"
#include "runtime/exercise_flags.h"
#include "runtime/process_runtime.h"

int main(int argc, char** argv) {
  CLI::App app{"The dynterrain DIS gateway: the exercise on IEEE 1278.1 UDP"};
  dt::ExerciseFlags flags;
  std::string name = "dis";
  std::string level = "info";
  flags.AddTo(app);
  app.add_option("--name", name, "the gateway's name in the exercise ([dis])")
      ->capture_default_str();
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    dt::log::Init(name, level);
    dt::ExerciseConfig exercise = flags.Load();
    dt::InstallStopSignals();
    std::filesystem::create_directories(exercise.run_dir);
    dt::dis::GatewayApp gateway(exercise, name);
    dt::ControlServer control(exercise.SocketPath(name),
                              [&](std::string_view line) { return gateway.Handle(line); });
    const int64_t tick_ms = 1000 / exercise.tick_hz;
    int64_t next_ms = dt::MonotonicMs();
    gateway.Start(next_ms);
    std::printf("READY %s\n", name.c_str());
    std::fflush(stdout);
    while (!dt::StopRequested() && !gateway.quit_requested()) {
      gateway.Tick(dt::MonotonicMs());
      control.Poll(0);
      next_ms += tick_ms;
      if (next_ms < dt::MonotonicMs() - tick_ms) next_ms = dt::MonotonicMs();
      for (int64_t left; (left = next_ms - dt::MonotonicMs()) > 0 && !dt::StopRequested() &&
                         !gateway.quit_requested();) {
        gateway.Wait(control, static_cast<int>(left));
        control.Poll(0);
      }
      gateway.Wait(control, 0);  // a tick that overran still hears the bus and the socket
    }
    DT_LOG_INFO("stopping: {} Entity States and {} Object States sent, {} entities imported",
                gateway.core().counters().entity_state_sent,
                gateway.core().counters().point_sent + gateway.core().counters().linear_sent,
                gateway.core().counters().vehicles_published);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_dis %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}
