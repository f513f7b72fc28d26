#include "node/scenario_runner.h"

#include <fmt/format.h>

#include "log/log.h"

namespace dt {

int ScenarioRunner::Advance(double elapsed_s, NodeActions& actions) {
  int ran = 0;
  while (next_ < scenario_.steps.size() && scenario_.steps[next_].at_s <= elapsed_s) {
    const ScenarioStep& step = scenario_.steps[next_++];
    ++ran;
    if (Status s = Run(step, actions); !s) {
      ++failed_;
      errors_.push_back(fmt::format("{}: {}", step.where, s.error().message));
      DT_LOG_WARN("scenario {}: {}", step.where, s.error().message);
    }
  }
  return ran;
}

Status ScenarioRunner::Run(const ScenarioStep& step, NodeActions& actions) {
  FeatureId target;
  if (!step.target.empty()) {
    auto it = names_.find(step.target);
    if (it == names_.end()) return Error{fmt::format("\"{}\" was never created", step.target)};
    target = it->second;
  }
  switch (step.action) {
    case ScenarioAction::kCreate: {
      Result<FeatureId> id = actions.Create(step.params);
      if (!id) return id.error();
      names_[step.name] = id.value();
      DT_LOG_INFO("scenario: created {} \"{}\"", id.value().ToString(), step.name);
      return Status::Ok();
    }
    case ScenarioAction::kUpdate: {
      std::optional<FeatureParams> old = actions.Params(target);
      if (!old)
        return Error{fmt::format("\"{}\" ({}) no longer exists", step.target, target.ToString())};
      Result<FeatureParams> p = ApplyFeatureEdit(*old, step.edit);
      if (!p) return p.error();
      return actions.Modify(target, p.value());
    }
    case ScenarioAction::kDestroy: {
      Status s = actions.Destroy(target);
      if (s) names_.erase(step.target);
      return s;
    }
    case ScenarioAction::kBreach: {
      Result<std::vector<FeatureId>> pieces =
          actions.Breach(target, step.gap_start_m, step.gap_width_m);
      if (!pieces) return pieces.error();
      names_.erase(step.target);
      for (size_t k = 0; k < pieces.value().size(); ++k) {
        names_[fmt::format("{}.{}", step.target, k + 1)] = pieces.value()[k];
      }
      return Status::Ok();
    }
    case ScenarioAction::kDrive: {
      Result<AppliedDrive> applied =
          actions.Drive(step.vehicle, step.speed_mps, step.heading_rate_rad_s);
      if (!applied) return applied.error();
      return Status::Ok();
    }
    case ScenarioAction::kSpawn: {
      Result<int> index = actions.Spawn(step.spawn);
      if (!index) return index.error();
      DT_LOG_INFO("scenario: spawned vehicle {} (a {})", index.value(), step.spawn.type);
      return Status::Ok();
    }
    case ScenarioAction::kRemove:
      return actions.Remove(step.vehicle);
    case ScenarioAction::kBlade:
      return actions.SetBlade(step.vehicle, step.blade_depth_m);
    case ScenarioAction::kWait:
      return Status::Ok();
  }
  return Status::Ok();
}

}  // namespace dt
