// dt_drill: runs a recovery drill (configs/drills/*.toml) and exits non-zero if a check fails.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "launcher/drill_config.h"
#include "launcher/drill_exercise_check.h"
#include "launcher/drill_runner.h"
#include "launcher/host_network.h"
#include "launcher/stop_signal_pipe.h"
#include "runtime/exercise_config.h"

int main(int argc, char** argv) {
  CLI::App app{"Run a dynterrain recovery drill"};
  std::string drill_path;
  std::string transport;
  std::string run_dir;
  dt::ProgramPaths programs = dt::ProgramPaths::BesideSelf();
  std::string node_bin = programs.node.string();
  std::string server_bin = programs.server.string();
  bool verbose = false;
  std::optional<uint64_t> seed;
  std::string hosts;
  std::string exercise_path;
  app.add_option("--drill", drill_path, "drill TOML (configs/drills/*.toml)")->required();
  app.add_option("--exercise", exercise_path,
                 "run the drill on this exercise file in place of its own (e.g. "
                 "configs/exercises/drill-geotiff.toml: the same drill on real ground)");
  app.add_option("--transport", transport, "override the exercise's transport URL");
  app.add_option("--run-dir", run_dir, "override the exercise's run_dir (emptied first)");
  app.add_option("--node-bin", node_bin, "the dt_node program")->capture_default_str();
  app.add_option("--server-bin", server_bin, "the dt_server program")->capture_default_str();
  app.add_option("--seed", seed,
                 "seed every random_ops and chaos action: the k-th (in time order) gets seed + k");
  app.add_option("--hosts", hosts,
                 "none, lan or wan: each process on a network namespace of its own (root; "
                 "replaces the exercise's [hosts] mode, docs/deploy.md)");
  app.add_flag("--verbose", verbose, "show every line of every process");
  CLI11_PARSE(app, argc, argv);

  try {
    dt::DrillConfig drill = dt::LoadDrillConfig(drill_path);
    if (seed) dt::OverrideSeeds(drill, *seed);
    if (!exercise_path.empty()) drill.exercise = std::filesystem::absolute(exercise_path);
    dt::ExerciseConfig exercise = dt::LoadExerciseConfig(drill.exercise);
    dt::ApplyOverrides(exercise, transport, run_dir);
    dt::ApplyHostsOverride(exercise, hosts);
    dt::CheckDrillAgainstExercise(drill, exercise);
    const int wake_fd = dt::InstallStopSignalPipe();
    if (wake_fd < 0) return 2;
    dt::DrillRunner runner(
        std::move(drill), std::move(exercise),
        dt::DrillOptions{
            // Drills start the server, standby and nodes only: no view, no DIS gateway.
            .programs = {.node = node_bin, .server = server_bin, .view = programs.view, .dis = {}},
            .transport_override = transport,
            .wake_fd = wake_fd,
            .echo_output = verbose,
        });
    return runner.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_drill: %s\n", e.what());
    return 2;
  }
}
