// CheckDrillAgainstExercise: refuses a drill whose actions name what its exercise lacks.
#pragma once

#include "launcher/drill_config.h"
#include "runtime/exercise_config.h"

namespace dt {

// Throws std::invalid_argument naming the drill action (or file) and what is missing: a server
// (the checks are about what one acknowledged and stored), a process or node an action names,
// or more chaos victims than targets. Run before DrillRunner, which assumes all of them.
void CheckDrillAgainstExercise(const DrillConfig& drill, const ExerciseConfig& exercise);

}  // namespace dt
