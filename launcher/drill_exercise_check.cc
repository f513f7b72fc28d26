#include "launcher/drill_exercise_check.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace dt {

void CheckDrillAgainstExercise(const DrillConfig& drill, const ExerciseConfig& exercise) {
  if (!exercise.server) {
    // The checks are about what the server acknowledged and stored.
    throw std::invalid_argument(
        fmt::format("{}: {} has no server ([protocol] require_server = false); drills need one",
                    drill.source.string(), exercise.source.string()));
  }
  for (const DrillAction& a : drill.actions) {
    for (const auto* list : {&a.targets, &a.from}) {
      for (const std::string& n : *list) {
        if (exercise.FindProcess(n) == nullptr) {
          throw std::invalid_argument(fmt::format("{}: {} has no process named \"{}\"", a.where,
                                                  exercise.source.string(), n));
        }
      }
    }
    const auto is_node = [&](const std::string& n) {
      return std::any_of(exercise.nodes.begin(), exercise.nodes.end(),
                         [&](const ProcessConfig& p) { return p.name == n; });
    };
    if (!a.owner.empty() && !is_node(a.owner)) {
      throw std::invalid_argument(fmt::format("{}: {} has no node named \"{}\" (owner)", a.where,
                                              exercise.source.string(), a.owner));
    }
    const bool vehicle_action =
        a.kind == DrillActionKind::kVehiclesSeen || a.kind == DrillActionKind::kSampleVehicles;
    for (const std::string& n : vehicle_action ? a.targets : std::vector<std::string>{}) {
      if (!is_node(n)) {
        throw std::invalid_argument(
            fmt::format("{}: \"{}\" is not a node (vehicle actions watch nodes)", a.where, n));
      }
    }
    if (a.kind == DrillActionKind::kChaos) {
      const size_t targets = a.targets.empty() ? exercise.Processes().size() : a.targets.size();
      if (static_cast<size_t>(a.max_down) > targets) {
        throw std::invalid_argument(fmt::format("{}: chaos max_down {} exceeds its {} targets",
                                                a.where, a.max_down, targets));
      }
    }
  }
}

}  // namespace dt
