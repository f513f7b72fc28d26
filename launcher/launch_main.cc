// dt_launch: starts a whole exercise (server, standby, nodes), prefixes their output, waits for
// every READY, and on Ctrl-C or SIGTERM stops them all by PID and reports how each ended.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "launcher/exercise_commands.h"
#include "launcher/host_network.h"
#include "launcher/stop_signal_pipe.h"
#include "launcher/supervisor.h"
#include "runtime/exercise_flags.h"

namespace {

void Say(const std::string& text) { dt::Supervisor::PrintPrefixed("launch", text); }

// The exit code of a bad config, the launcher's own and dt_node's and dt_server's.
constexpr int kConfigErrorExit = 2;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Launch a dynterrain exercise: server, standby and nodes"};
  dt::ExerciseFlags flags;
  dt::ProgramPaths programs = dt::ProgramPaths::BesideSelf();
  std::string node_bin = programs.node.string();
  std::string server_bin = programs.server.string();
  std::string view_bin = programs.view.string();
  std::string dis_bin = programs.dis.string();
  int ready_timeout_s = 120;
  int grace_ms = 10000;
  std::string hosts_mode;
  flags.AddTo(app);
  app.add_option("--hosts", hosts_mode,
                 "none, lan or wan: each process on a network namespace of its own (root; "
                 "replaces the exercise's [hosts] mode, docs/deploy.md)");
  app.add_option("--node-bin", node_bin, "the dt_node program")->capture_default_str();
  app.add_option("--server-bin", server_bin, "the dt_server program")->capture_default_str();
  app.add_option("--view-bin", view_bin, "the dt_view program (started when the file has a [view])")
      ->capture_default_str();
  app.add_option("--dis-bin", dis_bin, "the dt_dis program (started when the file has a [dis])")
      ->capture_default_str();
  app.add_option("--ready-timeout-s", ready_timeout_s, "give up if not all READY by then")
      ->check(CLI::Range(1, 3600))
      ->capture_default_str();
  app.add_option("--grace-ms", grace_ms, "after SIGTERM, SIGKILL children still running")
      ->check(CLI::Range(0, 600000))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  programs = {node_bin, server_bin, view_bin, dis_bin};

  dt::ExerciseConfig exercise;
  try {
    exercise = flags.Load();
    dt::ApplyHostsOverride(exercise, hosts_mode);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_launch: %s\n", e.what());
    return kConfigErrorExit;
  }

  const int wake_fd = dt::InstallStopSignalPipe();
  if (wake_fd < 0) return 1;

  // Hosts mode: made before the supervisor, so it is removed after the children have stopped.
  std::unique_ptr<dt::HostNetwork> hosts;
  std::string carrier = flags.transport_override;
  if (exercise.hosts.mode != dt::HostsMode::kNone) {
    try {
      std::filesystem::create_directories(exercise.run_dir);
      hosts = std::make_unique<dt::HostNetwork>(exercise);
      carrier =
          hosts->CarrierUrl(carrier.empty() ? exercise.transport_url : carrier, exercise.run_dir);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "dt_launch: %s\n", e.what());
      return kConfigErrorExit;
    }
    Say(fmt::format("hosts mode {}: every process on a host of its own, carrier {}",
                    dt::HostsModeName(exercise.hosts.mode), carrier));
  }
  // Children get the same overrides.
  std::vector<std::string> extra;
  if (!carrier.empty()) extra.insert(extra.end(), {"--transport", carrier});
  if (!flags.run_dir_override.empty()) {
    extra.insert(extra.end(), {"--run-dir", exercise.run_dir.string()});
  }
  auto command = [&](const dt::ProcessConfig& p) {
    std::vector<std::string> command_line = dt::ProcessCommand(exercise, p, programs, extra);
    return hosts ? hosts->OnHost(p.name, std::move(command_line)) : command_line;
  };
  dt::Supervisor sup;
  sup.set_wake_fd(wake_fd);
  int rc = 0;
  bool interrupted = false;
  try {
    // The server first: nodes sign on to it. An exercise without one starts its nodes at once.
    std::vector<std::string> servers;
    if (exercise.server) servers.push_back(exercise.server->name);
    if (exercise.standby) servers.push_back(exercise.standby->name);
    for (const std::string& n : servers) {
      sup.Start(n, command(*exercise.FindProcess(n)));
    }
    dt::Status s = sup.WaitReady(servers, ready_timeout_s * 1000);
    std::vector<std::string> all = servers;
    if (s) {
      for (const dt::ProcessConfig& n : exercise.nodes) {
        sup.Start(n.name, command(n));
        all.push_back(n.name);
      }
      s = sup.WaitReady(all, ready_timeout_s * 1000);
    }
    // The view and the DIS gateway last: they observe, and nothing waits for them (docs/view.md,
    // docs/dis.md).
    for (const dt::ProcessConfig* p : {exercise.view ? &exercise.view->process : nullptr,
                                       exercise.dis ? &exercise.dis->process : nullptr}) {
      if (!s || p == nullptr) continue;
      sup.Start(p->name, command(*p));
      all.push_back(p->name);
      s = sup.WaitReady(all, ready_timeout_s * 1000);
    }
    if (!s) {
      Say("exercise failed to start: " + s.error().message);
      rc = 1;
      // dt_node and dt_server exit 2 for a bad config (docs/node.md): a child that did so before
      // the exercise was ready found the exercise's config bad, so the launcher exits as it
      // would for a config it refused itself (docs/launcher.md).
      for (const std::string& n : sup.names()) {
        const int st = sup.last_wait_status(n);
        if (!sup.running(n) && WIFEXITED(st) && WEXITSTATUS(st) == kConfigErrorExit) {
          rc = kConfigErrorExit;
        }
      }
    } else {
      Say(fmt::format("all {} processes ready", all.size()));
      std::printf("READY %s\n", exercise.name.c_str());
      std::fflush(stdout);
      // Runs until a signal, or until every child has ended on its own.
      while (sup.any_running()) {
        if (sup.Poll(1000)) {
          interrupted = true;
          break;
        }
      }
    }
  } catch (const std::exception& e) {
    Say(std::string("error: ") + e.what());
    rc = 1;
  }
  if (interrupted) Say("stopping every process");
  sup.StopAll(grace_ms);
  for (const std::string& n : sup.names()) {
    const int st = sup.last_wait_status(n);
    Say(fmt::format("{}: {}", n, dt::DescribeWaitStatus(st)));
    if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) rc = rc == 0 ? 1 : rc;
  }
  return rc;
}
