// dt_ctl: sends one command to a running node or server over its control socket, e.g.
//   dt_ctl --config configs/exercises/demo.toml --name node-2 crater 100 200 5
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "runtime/control_client.h"
#include "runtime/control_command.h"
#include "runtime/exercise_config.h"
#include "runtime/vehicle_listing.h"

int main(int argc, char** argv) {
  CLI::App app{"Send a command to a running dynterrain process.\nCommands:\n" + dt::ControlUsage()};
  std::string config_path;
  std::string name;
  int timeout_ms = 10000;
  std::vector<std::string> words;
  app.add_option("--config", config_path, "exercise TOML")->required();
  std::string transport_override;
  std::string run_dir_override;
  app.add_option("--transport", transport_override, "override the exercise's transport URL");
  app.add_option("--run-dir", run_dir_override, "override the exercise's run_dir");
  app.add_option("--name", name, "the process to talk to (node-1, server, ...)")->required();
  app.add_option("--timeout-ms", timeout_ms, "give up waiting for the reply")
      ->check(CLI::Range(1, 3600000))
      ->capture_default_str();
  app.add_option("command", words, "the command and its arguments")->required();
  app.allow_extras(false);
  app.prefix_command(false);
  // Every word from the command on is the command's: a negative number or -inf is an argument
  // for the command parser to judge, not an option (docs/node.md "Control socket").
  app.positionals_at_end(true);
  CLI11_PARSE(app, argc, argv);

  // `vehicles` from dt_ctl is a page unless asked for more: a node of 30 000 vehicles would
  // answer 6 MB (docs/node.md "Control socket").
  if (words[0] == "vehicles" && std::find(words.begin(), words.end(), "--limit") == words.end() &&
      std::find(words.begin(), words.end(), "--all") == words.end()) {
    words.push_back("--limit");
    words.push_back(std::to_string(dt::kDefaultVehicleLimit));
  }
  std::string line;
  for (const std::string& w : words) line += (line.empty() ? "" : " ") + w;
  try {
    dt::ExerciseConfig exercise = dt::LoadExerciseConfig(config_path, dt::GroundReading::kSkip);
    dt::ApplyOverrides(exercise, transport_override, run_dir_override);
    if (exercise.FindProcess(name) == nullptr) {
      std::fprintf(stderr, "dt_ctl: %s has no process named \"%s\"\n", config_path.c_str(),
                   name.c_str());
      return 2;
    }
    dt::Result<dt::ControlReply> reply =
        dt::CallControl(exercise.SocketPath(name), line, timeout_ms);
    if (!reply) {
      std::fprintf(stderr, "dt_ctl: %s\n", reply.error().message.c_str());
      return 2;
    }
    if (!reply.value().ok) {
      std::fprintf(stderr, "error: %s\n", reply.value().error.c_str());
      return 1;
    }
    if (!reply.value().body.empty()) std::printf("%s\n", reply.value().body.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_ctl: %s\n", e.what());
    return 2;
  }
}
