// The deterministic simulation of the protocol: nodes, a server (sometimes a standby) over a
// SimNetwork with seeded loss, duplication, delay, reordering, partitions and crashes, then a
// healed network; checks the guarantee of docs/protocol.md after every schedule.
//
//   DT_SIM_SEEDS=<n>       seeds to run (default 1000), starting at DT_SIM_FIRST_SEED (default 1)
//   DT_SIM_SEED=<s>        run only seed s (reproduces a failure exactly)
//   DT_SIM_TRACE=1         print the schedule's events; DT_SIM_LOG=info the replicas' log lines
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "log/log.h"
#include "simulation/protocol_sim.h"

namespace dt::sim {
namespace {

int64_t EnvInt(const char* name, int64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtoll(v, nullptr, 10) : fallback;
}

TEST(ProtocolSimTest, TheGuaranteeHoldsForEverySeed) {
  log::Init("sim", std::getenv("DT_SIM_LOG") != nullptr ? std::getenv("DT_SIM_LOG") : "error");
  const int64_t only = EnvInt("DT_SIM_SEED", 0);
  const int64_t first = only > 0 ? only : EnvInt("DT_SIM_FIRST_SEED", 1);
  const int64_t count = only > 0 ? 1 : EnvInt("DT_SIM_SEEDS", 1000);
  const auto dir = std::filesystem::temp_directory_path() /
                   fmt::format("dt_protocol_sim_{}", static_cast<long>(::getpid()));
  int failures = 0;
  int64_t sqlite_seeds = 0;
  int64_t simulated_ms = 0;
  int observer_drop_seeds = 0;
  std::string observer_drop_list;  // the first of those seeds, to look at one
  uint64_t observer_dropped = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  for (int64_t seed = first; seed < first + count; ++seed) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    sqlite_seeds += seed % 10 == 3 ? 1 : 0;
    SimRun run(static_cast<uint64_t>(seed), dir);
    const std::string failure = run.Run();
    simulated_ms += run.simulated_ms();
    if (run.observer_dropped() > 0 && ++observer_drop_seeds <= 20) {
      observer_drop_list += fmt::format(" {}", seed);
    }
    observer_dropped += run.observer_dropped();
    if (!failure.empty()) {
      ++failures;
      ADD_FAILURE() << "seed " << seed << ": " << failure << "\n  reproduce: DT_SIM_SEED=" << seed
                    << " " << ::testing::UnitTest::GetInstance()->original_working_dir()
                    << "/protocol_sim_test";
      if (failures >= 10) break;
    }
  }
  const double wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start)
          .count();
  std::filesystem::remove_all(dir);
  RecordProperty("seeds", static_cast<int>(count));
  std::printf("%lld seeds from %lld (%lld with SQLite files): %d failed\n",
              static_cast<long long>(count), static_cast<long long>(first),
              static_cast<long long>(sqlite_seeds), failures);
  std::printf("%d seeds had the observer drop changes only it held (%llu changes):%s%s\n",
              observer_drop_seeds, static_cast<unsigned long long>(observer_dropped),
              observer_drop_list.c_str(), observer_drop_seeds > 20 ? " ..." : "");
  // A figure, not a check: how long runs of many seeds take (docs/performance.md).
  std::printf("simulated %.1f s in %.1f s wall (%.0fx real time), %.1f ms wall per seed\n",
              static_cast<double>(simulated_ms) / 1000.0, wall_ms / 1000.0,
              wall_ms > 0 ? static_cast<double>(simulated_ms) / wall_ms : 0.0,
              count > 0 ? wall_ms / static_cast<double>(count) : 0.0);
  std::printf("%lld earth moves issued by blade operations\n",
              static_cast<long long>(earth_moves_issued));
  // Blade work is in the schedules: a run of a few seeds issues some.
  if (count >= 10) {
    EXPECT_GT(earth_moves_issued, 0);
  }
}

}  // namespace
}  // namespace dt::sim
