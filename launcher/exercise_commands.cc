#include "launcher/exercise_commands.h"

#include <unistd.h>

namespace dt {

ProgramPaths ProgramPaths::BesideSelf() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path dir = ec ? std::filesystem::path(".") : self.parent_path();
  return {.node = dir / ".." / "node" / "dt_node",
          .server = dir / ".." / "server" / "dt_server",
          .view = dir / ".." / "view" / "dt_view",
          .dis = dir / ".." / "dis" / "dt_dis"};
}

std::vector<std::string> ProcessCommand(const ExerciseConfig& exercise,
                                        const ProcessConfig& process, const ProgramPaths& programs,
                                        const std::vector<std::string>& extra) {
  const bool is_server = (exercise.server && &process == &*exercise.server) ||
                         (exercise.standby && &process == &*exercise.standby);
  const bool is_view = exercise.view && &process == &exercise.view->process;
  const bool is_dis = exercise.dis && &process == &exercise.dis->process;
  const std::filesystem::path& program = is_view  ? programs.view
                                         : is_dis ? programs.dis
                                                  : (is_server ? programs.server : programs.node);
  std::vector<std::string> argv = {program.string(), "--config",
                                   std::filesystem::absolute(exercise.source).string(), "--name",
                                   process.name};
  if (exercise.standby && &process == &*exercise.standby) argv.push_back("--standby");
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

}  // namespace dt
