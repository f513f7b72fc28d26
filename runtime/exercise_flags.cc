#include "runtime/exercise_flags.h"

namespace dt {

void ExerciseFlags::AddTo(CLI::App& app) {
  app.add_option("--config", config_path, "exercise TOML (configs/exercises/*.toml)")->required();
  app.add_option("--transport", transport_override, "override the exercise's transport URL");
  app.add_option("--run-dir", run_dir_override, "override the exercise's run_dir");
}

ExerciseConfig ExerciseFlags::Load() const {
  ExerciseConfig exercise = LoadExerciseConfig(config_path);
  ApplyOverrides(exercise, transport_override, run_dir_override);
  return exercise;
}

}  // namespace dt
