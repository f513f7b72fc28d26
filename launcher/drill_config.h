// DrillConfig: a recovery drill read from TOML: an exercise, a timeline of operations and
// faults, and the time allowed to converge (docs/launcher.md "Drill files").
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace dt {

enum class DrillActionKind {
  kRandomOps,       // a burst of random creates, updates and destroys on some nodes
  kKill,            // SIGKILL a process
  kStop,            // SIGTERM a process and wait for it to end
  kRestart,         // start a process again (a node with no local state; a server on its database)
  kLoss,            // receive drop probability on some processes
  kPartition,       // cut `targets` off from `from`, both ways
  kHeal,            // end every partition
  kCommand,         // one control command on some processes (must succeed)
  kChaos,           // rounds of SIGKILL on random processes, each restarted after a random downtime
  kVehiclesSeen,    // wait until some nodes hold (or no longer hold) a node's vehicles
  kSampleVehicles,  // sample nodes' remote vehicles: their tilt, their error against the owner
  kVehicleReaches,  // wait until a node's vehicle is alive inside a box (past an obstacle)
  kDigest,          // wait for one digest everywhere; remember it, or check it equals the one kept
};

struct DrillAction {
  double at_s = 0.0;
  DrillActionKind kind = DrillActionKind::kHeal;
  std::vector<std::string> targets;  // process names; empty: every process
  std::vector<std::string> from;     // partition
  int count = 0;                     // random ops
  double duration_s = 0.0;           // random ops, chaos
  uint64_t seed = 1;                 // random ops, chaos
  double period_s = 10.0;            // chaos: mean time between kill rounds (jittered +-50 %)
  int max_down = 1;                  // chaos: at most this many processes down at once
  double down_min_s = 1.0;           // chaos: each kill's downtime, uniform in [min, max]
  double down_max_s = 5.0;
  double drop_probability = 0.0;  // loss
  std::string line;   // command; "{name}": the ID a command kept `as` name; "{run_dir}": run_dir
  std::string as;     // command: keep the reply's (first) feature ID under this name
  std::string owner;  // vehicle actions: the node whose vehicles are watched
  bool seen = true;   // vehicles_seen: held (true) or gone (false)
  double within_s = 15.0;      // vehicles_seen, vehicle_reaches, digest: the time allowed
  double not_before_s = 0.0;   // vehicles_seen: and not sooner than this
  double min_tilt_deg = -1.0;  // sample_vehicles: the largest |pitch| or |roll| seen; <0 unchecked
  double error_m = 1.0;        // sample_vehicles: a sample is within when its error is <= this
  double min_fraction = -1.0;  // sample_vehicles: of samples within error_m; <0 unchecked
  size_t vehicle = 0;          // vehicle_reaches: the owner's local index
  double x_min_m = -1e300, x_max_m = 1e300;  // vehicle_reaches: the box (open sides unbounded)
  double z_min_m = -1e300, z_max_m = 1e300;
  std::string mark;   // digest: the name the digest is kept under
  std::string where;  // "<file> action <n>"
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
// against the exercise by CheckDrillAgainstExercise (launcher/drill_exercise_check.h).
DrillConfig ParseDrillConfig(std::string_view toml_text, std::string_view source_name,
                             const std::filesystem::path& base_dir);
DrillConfig LoadDrillConfig(const std::filesystem::path& path);

// The names a command line refers to as "{name}", in order.
std::vector<std::string> NamesUsed(std::string_view line);
// The line with every "{name}" of `kept` replaced by its value (others left as they are).
std::string WithNames(std::string_view line, const std::map<std::string, std::string>& kept);

// Gives the k-th seeded action of the timeline (random_ops, chaos; in time order, from 0) the
// seed `seed + k`, so one number reproduces a whole campaign's choices (dt_drill --seed).
void OverrideSeeds(DrillConfig& drill, uint64_t seed);

}  // namespace dt
