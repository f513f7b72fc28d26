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
  std::filesystem::path view;    // dt_view (docs/view.md); empty: the view is not started
  std::filesystem::path dis;     // dt_dis (docs/dis.md); empty: the gateway is not started
  // Beside this program in a build tree: <dir>/../node/dt_node, <dir>/../server/dt_server,
  // <dir>/../view/dt_view, <dir>/../dis/dt_dis.
  static ProgramPaths BesideSelf();
};

// "dt_server --config C --name server [--standby]", "dt_view --config C --name view",
// "dt_dis --config C --name dis" or
// "dt_node --config C --name node-1", plus
// `extra` (e.g. "--fresh").
std::vector<std::string> ProcessCommand(const ExerciseConfig& exercise,
                                        const ProcessConfig& process, const ProgramPaths& programs,
                                        const std::vector<std::string>& extra = {});

}  // namespace dt
