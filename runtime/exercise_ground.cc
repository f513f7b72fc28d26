#include "runtime/exercise_ground.h"

#include <fmt/format.h>

#include "terrain/random_terrain.h"

namespace dt {

BaseGround BuildExerciseGround(const ExerciseConfig& exercise) {
  if (exercise.ground) return *exercise.ground;
  return BaseGround{MakeRandomTerrain(exercise.terrain), {}};
}

std::string ExerciseGroundSource(const ExerciseConfig& exercise) {
  if (exercise.ground) return fmt::format("ground_file {}", exercise.ground_file.string());
  const RandomTerrainParams& t = exercise.terrain;
  return fmt::format("random seed {} {}x{} posts spacing {} m relief {} m", t.seed, t.posts_x,
                     t.posts_z, t.spacing_m, t.relief_m);
}

}  // namespace dt
