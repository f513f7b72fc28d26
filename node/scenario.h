// Scenario: a node's timeline of feature edits and vehicle commands, read from TOML.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/feature_edit.h"
#include "runtime/node_actions.h"
#include "terrain/feature_params.h"

namespace dt {

enum class ScenarioAction {
  kCreate,
  kUpdate,
  kDestroy,
  kBreach,
  kDrive,
  kWait,
  kSpawn,
  kRemove,
  kBlade
};

// One step (docs/node.md "Scenario files"). Feature steps name features locally: a create gives
// `name`, later steps refer to it by `target`; a breach names its pieces `<target>.1`,
// `<target>.2`.
struct ScenarioStep {
  double at_s = 0.0;  // from the scenario's start
  ScenarioAction action = ScenarioAction::kWait;
  std::string name;          // create
  std::string target;        // update, destroy, breach
  FeatureParams params;      // create: the whole feature
  FeatureEdit edit;          // update: the changed keys
  double gap_start_m = 0.0;  // breach: from the berm's first end along its axis
  double gap_width_m = 0.0;
  int vehicle = 0;                      // drive, remove, blade
  std::optional<double> blade_depth_m;  // blade: lowered to this depth; nullopt: raised
  SpawnRequest spawn;                   // spawn
  double speed_mps = 0.0;
  double heading_rate_rad_s = 0.0;
  double duration_s = 0.0;  // drive: then the vehicle stops; wait: the pause
  std::string where;        // "<file> step <n>", for messages
};

struct Scenario {
  std::string source;
  std::vector<ScenarioStep> steps;  // sorted by at_s (stable)
  double end_s() const { return steps.empty() ? 0.0 : steps.back().at_s; }
};

// Parses and checks the whole timeline before anything runs: every key and value, that names are
// unique, that targets were created earlier and not destroyed, that breaches target berms, that
// times never go back, and that vehicle indices are below the vehicles there are at that step
// (vehicle_count, plus the spawns, minus the removals before it). Throws
// std::invalid_argument naming the source, the step, the key and the value.
Scenario ParseScenario(std::string_view toml_text, std::string_view source_name, int vehicle_count);
Scenario LoadScenario(const std::filesystem::path& path, int vehicle_count);

}  // namespace dt
