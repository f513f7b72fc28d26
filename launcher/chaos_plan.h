// ChaosPlan: the seeded schedule of a drill's chaos action (kill rounds, victims, downtimes).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dt {

struct ChaosSettings {
  double duration_s = 0.0;  // rounds start in [0, duration_s) after the action begins
  double period_s = 10.0;   // mean gap between rounds; each gap is uniform in [0.5, 1.5] x this
  int max_down = 1;         // a round kills 1..max_down processes (uniformly)
  double down_min_s = 1.0;  // each victim's downtime is uniform in [down_min_s, down_max_s]
  double down_max_s = 5.0;
  uint64_t seed = 1;
};

struct ChaosRound {
  double at_s = 0.0;  // after the action begins
  int count = 1;      // processes to kill
  // Every target in a seeded order: the round kills the first `count` that are running and not
  // already down (fewer if max_down are down already).
  std::vector<std::string> order;
  std::vector<double> down_s;  // downtime of the round's 1st, 2nd, ... victim (max_down values)
};

// The whole schedule, a function of the settings and targets alone (mt19937_64 with our own
// uniform draws and shuffle, so it is the same on every standard library). Throws
// std::invalid_argument for no targets, max_down outside [1, targets], a period that is not > 0
// or a downtime range that is empty or negative.
std::vector<ChaosRound> PlanChaos(const ChaosSettings& settings,
                                  const std::vector<std::string>& targets);

}  // namespace dt
