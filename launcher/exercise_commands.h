// Exercise commands: the command line that starts each process of an exercise.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "runtime/exercise_config.h"

namespace dt {

struct ProgramPaths {
  std::filesystem::path node;    // dt_node
  std::filesystem::path server;  // dt_server
  // Beside this program in a build tree: <dir>/../node/dt_node, <dir>/../server/dt_server.
  static ProgramPaths BesideSelf();
};

// "dt_server --config C --name server [--standby]" or "dt_node --config C --name node-1", plus
// `extra` (e.g. "--fresh").
std::vector<std::string> ProcessCommand(const ExerciseConfig& exercise,
                                        const ProcessConfig& process, const ProgramPaths& programs,
                                        const std::vector<std::string>& extra = {});

}  // namespace dt
