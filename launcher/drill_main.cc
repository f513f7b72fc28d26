// dt_drill: runs a recovery drill (configs/drills/*.toml) and exits non-zero if a check fails.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <optional>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "launcher/drill_config.h"
#include "launcher/drill_runner.h"
#include "launcher/stop_signal_pipe.h"

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
  app.add_option("--drill", drill_path, "drill TOML (configs/drills/*.toml)")->required();
  app.add_option("--transport", transport, "override the exercise's transport URL");
  app.add_option("--run-dir", run_dir, "override the exercise's run_dir (emptied first)");
  app.add_option("--node-bin", node_bin, "the dt_node program")->capture_default_str();
  app.add_option("--server-bin", server_bin, "the dt_server program")->capture_default_str();
  app.add_option("--seed", seed,
                 "seed every random_ops and chaos action: the k-th (in time order) gets seed + k");
  app.add_flag("--verbose", verbose, "show every line of every process");
  CLI11_PARSE(app, argc, argv);

  dt::DrillConfig drill;
  dt::ExerciseConfig exercise;
  try {
    drill = dt::LoadDrillConfig(drill_path);
    if (seed) dt::OverrideSeeds(drill, *seed);
    exercise = dt::LoadExerciseConfig(drill.exercise);
    dt::ApplyOverrides(exercise, transport, run_dir);
    if (!exercise.server) {
      // The checks are about what the server acknowledged and stored.
      throw std::invalid_argument(
          fmt::format("{}: {} has no server ([protocol] require_server = false); drills need one",
                      drill_path, exercise.source.string()));
    }
    for (const dt::DrillAction& a : drill.actions) {
      for (const auto* list : {&a.targets, &a.from}) {
        for (const std::string& n : *list) {
          if (exercise.FindProcess(n) == nullptr) {
            throw std::invalid_argument(fmt::format("{}: {} has no process named \"{}\"", a.where,
                                                    exercise.source.string(), n));
          }
        }
      }
      const auto is_node = [&](const std::string& n) {
        return std::any_of(exercise.nodes.begin(), exercise.nodes.end(),
                           [&](const dt::ProcessConfig& p) { return p.name == n; });
      };
      if (!a.owner.empty() && !is_node(a.owner)) {
        throw std::invalid_argument(fmt::format("{}: {} has no node named \"{}\" (owner)", a.where,
                                                exercise.source.string(), a.owner));
      }
      const bool vehicle_action = a.kind == dt::DrillActionKind::kVehiclesSeen ||
                                  a.kind == dt::DrillActionKind::kSampleVehicles;
      for (const std::string& n : vehicle_action ? a.targets : std::vector<std::string>{}) {
        if (!is_node(n)) {
          throw std::invalid_argument(
              fmt::format("{}: \"{}\" is not a node (vehicle actions watch nodes)", a.where, n));
        }
      }
      if (a.kind == dt::DrillActionKind::kChaos) {
        const size_t targets = a.targets.empty() ? exercise.Processes().size() : a.targets.size();
        if (static_cast<size_t>(a.max_down) > targets) {
          throw std::invalid_argument(fmt::format("{}: chaos max_down {} exceeds its {} targets",
                                                  a.where, a.max_down, targets));
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_drill: %s\n", e.what());
    return 2;
  }
  const int wake_fd = dt::InstallStopSignalPipe();
  if (wake_fd < 0) return 2;

  dt::DrillOptions options;
  // Drills start the server, standby and nodes only: no view, no DIS gateway.
  options.programs = {node_bin, server_bin, programs.view, {}};
  options.transport_override = transport;
  options.wake_fd = wake_fd;
  options.echo_output = verbose;
  dt::DrillRunner runner(std::move(drill), std::move(exercise), options);
  return runner.Run();
}
