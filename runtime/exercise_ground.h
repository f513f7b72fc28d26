// BuildExerciseGround: the ground every process of an exercise starts on, from its [terrain].
#pragma once

#include <string>

#include "runtime/exercise_config.h"
#include "terrain/base_ground.h"

namespace dt {

// The one place a process builds its ground from the exercise file: the saved terrain of
// [terrain] ground_file (read when the file was loaded) with its features, else seeded random
// ground without features. Every member of an exercise must build the same (docs/pdu.md "Ground
// identity").
BaseGround BuildExerciseGround(const ExerciseConfig& exercise);

// What the ground came from, for messages and `status`: "ground_file <path>" or
// "random seed <n> <x>x<z> posts spacing <m> m relief <m> m".
std::string ExerciseGroundSource(const ExerciseConfig& exercise);

}  // namespace dt
