#include "launcher/chaos_plan.h"

#include <random>
#include <stdexcept>

#include <fmt/format.h>

#include "launcher/seeded_draws.h"

namespace dt {

std::vector<ChaosRound> PlanChaos(const ChaosSettings& s, const std::vector<std::string>& targets) {
  if (targets.empty()) throw std::invalid_argument("chaos needs at least one target");
  if (s.max_down < 1 || static_cast<size_t>(s.max_down) > targets.size()) {
    throw std::invalid_argument(fmt::format("chaos max_down {} is outside [1, {}] (its targets)",
                                            s.max_down, targets.size()));
  }
  if (!(s.period_s > 0.0) || !(s.duration_s >= 0.0)) {
    throw std::invalid_argument(fmt::format("chaos period_s {} must be > 0 and duration_s {} >= 0",
                                            s.period_s, s.duration_s));
  }
  if (!(s.down_min_s >= 0.0) || !(s.down_max_s >= s.down_min_s)) {
    throw std::invalid_argument(
        fmt::format("chaos downtime [{}, {}] s is not a range", s.down_min_s, s.down_max_s));
  }
  std::mt19937_64 rng(s.seed);
  std::vector<ChaosRound> rounds;
  for (double t = SeededUniform(rng, 0.5, 1.5) * s.period_s; t < s.duration_s;
       t += SeededUniform(rng, 0.5, 1.5) * s.period_s) {
    ChaosRound r;
    r.at_s = t;
    r.count = 1 + static_cast<int>(rng() % static_cast<uint64_t>(s.max_down));
    r.order = targets;
    SeededShuffle(rng, r.order);
    for (int i = 0; i < s.max_down; ++i) {
      r.down_s.push_back(SeededUniform(rng, s.down_min_s, s.down_max_s));
    }
    rounds.push_back(std::move(r));
  }
  return rounds;
}

}  // namespace dt
