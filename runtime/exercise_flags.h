// ExerciseFlags: the command-line flags shared by every program that runs an exercise.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "runtime/exercise_config.h"

namespace dt {

// --config (required), --transport and --run-dir, as dt_node, dt_server and dt_launch take them.
struct ExerciseFlags {
  std::string config_path;
  std::string transport_override;  // empty: the exercise's own
  std::string run_dir_override;    // empty: the exercise's own

  void AddTo(CLI::App& app);
  // Loads the exercise file and applies the overrides. Throws like LoadExerciseConfig and
  // ApplyOverrides, naming the file and the bad value.
  ExerciseConfig Load() const;
};

}  // namespace dt
