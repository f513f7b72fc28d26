// ScenarioRunner: plays a node's scenario against its actions as time passes.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "runtime/node_actions.h"
#include "node/scenario.h"

namespace dt {

// Runs each step once its time has come. A step that fails at run time (another node destroyed
// its target meanwhile, say) is logged, counted and skipped; the scenario goes on.
class ScenarioRunner {
 public:
  explicit ScenarioRunner(Scenario scenario) : scenario_(std::move(scenario)) {}

  // Runs every step with at_s <= elapsed_s not yet run. Returns the number run.
  int Advance(double elapsed_s, NodeActions& actions);

  bool done() const { return next_ >= scenario_.steps.size(); }
  int failed() const { return failed_; }
  // The IDs the local names stand for (created and not destroyed by this scenario).
  const std::map<std::string, FeatureId>& names() const { return names_; }
  // Messages of the failed steps, in order.
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  Status Run(const ScenarioStep& step, NodeActions& actions);

  Scenario scenario_;
  size_t next_ = 0;
  int failed_ = 0;
  std::map<std::string, FeatureId> names_;
  std::vector<std::string> errors_;
};

}  // namespace dt
