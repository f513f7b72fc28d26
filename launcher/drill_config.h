// DrillConfig: a recovery drill read from TOML: an exercise, a timeline of operations and
// faults, and the time allowed to converge (docs/launcher.md "Drill files").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dt {

enum class DrillActionKind {
  kRandomOps,  // a burst of random creates, updates and destroys on some nodes
  kKill,       // SIGKILL a process
  kStop,       // SIGTERM a process and wait for it to end
  kRestart,    // start a process again (a node with no local state; a server on its database)
  kLoss,       // receive drop probability on some processes
  kPartition,  // cut `targets` off from `from`, both ways
  kHeal,       // end every partition
  kCommand,    // one control command on some processes (must succeed)
};

struct DrillAction {
  double at_s = 0.0;
  DrillActionKind kind = DrillActionKind::kHeal;
  std::vector<std::string> targets;  // process names; empty: every process
  std::vector<std::string> from;     // partition
  int count = 0;                     // random ops
  double duration_s = 0.0;           // random ops
  uint64_t seed = 1;                 // random ops
  double drop_probability = 0.0;     // loss
  std::string line;                  // command
  std::string where;                 // "<file> action <n>"
};

struct DrillConfig {
  std::filesystem::path source;
  std::string name;
  std::filesystem::path exercise;    // absolute
  double deadline_s = 60.0;          // the whole drill, start to report
  double settle_s = 20.0;            // after the timeline: time to reach equal digests
  double ready_timeout_s = 20.0;     // for every READY at start and after restarts
  std::vector<DrillAction> actions;  // sorted by at_s (stable)
};

// Throws std::invalid_argument naming the file, key and value. Process names are checked
// against the exercise by the runner.
DrillConfig ParseDrillConfig(std::string_view toml_text, std::string_view source_name,
                             const std::filesystem::path& base_dir);
DrillConfig LoadDrillConfig(const std::filesystem::path& path);

}  // namespace dt
