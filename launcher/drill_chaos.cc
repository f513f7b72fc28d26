// DrillRunner's chaos action: rounds of SIGKILL on random targets from a seeded plan
// (launcher/chaos_plan.h), each victim restarted after its downtime and awaited until READY,
// while the drill's other actions (random operations) go on.
#include <algorithm>
#include <cstdio>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "launcher/drill_runner.h"

namespace dt {

void DrillRunner::StartChaos(const DrillAction& a) {
  ChaosSettings s;
  s.duration_s = a.duration_s;
  s.period_s = a.period_s;
  s.max_down = a.max_down;
  s.down_min_s = a.down_min_s;
  s.down_max_s = a.down_max_s;
  s.seed = a.seed;
  Chaos c{&a, ElapsedS(), PlanChaos(s, Expand(a.targets)), 0, {}, {}};
  std::printf(
      "[drill] chaos: seed %llu, %zu rounds over %.0f s (mean period %.1f s), up to %d "
      "down at once, downtime %.1f..%.1f s\n",
      static_cast<unsigned long long>(a.seed), c.plan.size(), a.duration_s, a.period_s, a.max_down,
      a.down_min_s, a.down_max_s);
  std::fflush(stdout);
  chaos_.push_back(std::move(c));
}

void DrillRunner::KillRound(Chaos& c, size_t index) {
  const ChaosRound& round = c.plan[index];
  const size_t room = static_cast<size_t>(c.action->max_down) - c.down.size();
  const size_t want = std::min(static_cast<size_t>(round.count), room);
  std::vector<std::string> victims;
  for (const std::string& n : round.order) {
    if (victims.size() >= want) break;
    if (sup_.running(n) && c.down.count(n) == 0) victims.push_back(n);
  }
  std::string what;
  if (victims.empty()) {
    what = want == 0 ? "nothing (max_down already down)" : "nothing (no target running)";
  } else {
    std::vector<std::string> downs;
    for (size_t i = 0; i < victims.size(); ++i)
      downs.push_back(fmt::format("{:.1f}", round.down_s[i]));
    what = fmt::format("{} (down {} s)", fmt::join(victims, ", "), fmt::join(downs, ", "));
  }
  std::printf("[drill] %.1f s: chaos round %zu/%zu: kill -9 %s\n", ElapsedS(), index + 1,
              c.plan.size(), what.c_str());
  std::fflush(stdout);
  for (size_t i = 0; i < victims.size(); ++i) {
    KillNow(victims[i]);
    c.waiting.erase(victims[i]);
    c.down[victims[i]] = ElapsedS() + round.down_s[i];
  }
}

bool DrillRunner::ChaosStep(Chaos& c, double& next_due_s) {
  for (auto it = c.down.begin(); it != c.down.end();) {
    if (it->second > ElapsedS()) {
      next_due_s = std::min(next_due_s, it->second);
      ++it;
      continue;
    }
    std::printf("[drill] %.1f s: chaos: restart %s\n", ElapsedS(), it->first.c_str());
    std::fflush(stdout);
    StartProcess(it->first);
    c.waiting[it->first] = ElapsedS();
    it = c.down.erase(it);
  }
  for (auto it = c.waiting.begin(); it != c.waiting.end();) {
    const std::string& n = it->first;
    const double waited_s = ElapsedS() - it->second;
    if (sup_.ready(n)) {
      std::printf("[drill] %.1f s: chaos: %s READY %.1f s after its restart\n", ElapsedS(),
                  n.c_str(), waited_s);
    } else if (!sup_.running(n)) {
      Check("chaos: restarted " + n + " READY", false,
            "it " + DescribeWaitStatus(sup_.last_wait_status(n)));
      stopped_.insert(n);  // reported here, not again as "ended by itself"
    } else if (waited_s > drill_.ready_timeout_s) {
      const std::string word = sup_.last_word(n);  // as WaitReady's timeout says it
      Check("chaos: restarted " + n + " READY", false,
            fmt::format("not READY {:.0f} s after its restart{}", drill_.ready_timeout_s,
                        word.empty() ? "" : fmt::format(" (its last word: \"{}\")", word)));
    } else {
      ++it;
      continue;
    }
    std::fflush(stdout);
    it = c.waiting.erase(it);
  }
  while (c.next < c.plan.size() && c.start_s + c.plan[c.next].at_s <= ElapsedS()) {
    KillRound(c, c.next++);
  }
  if (c.next < c.plan.size()) next_due_s = std::min(next_due_s, c.start_s + c.plan[c.next].at_s);
  return c.next < c.plan.size() || !c.down.empty() || !c.waiting.empty();
}

}  // namespace dt
