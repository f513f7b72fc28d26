// DrillRunner: runs a drill against a real exercise (processes, sockets, transport) and checks
// the protocol's guarantee at the end (docs/launcher.md "Drills").
#pragma once

#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "launcher/drill_config.h"
#include "launcher/exercise_commands.h"
#include "launcher/supervisor.h"
#include "runtime/control_protocol.h"
#include "runtime/exercise_config.h"
#include "terrain/feature_id.h"
#include "terrain/result.h"

namespace dt {

struct DrillOptions {
  ProgramPaths programs;
  std::string transport_override;  // empty: the exercise's
  int wake_fd = -1;                // readable: stop early (Ctrl-C)
  bool echo_output = false;        // every child line to stdout, not only warnings and READY
};

class DrillRunner {
 public:
  // The exercise's run_dir is emptied first: a drill starts with no state.
  DrillRunner(DrillConfig drill, ExerciseConfig exercise, DrillOptions options);

  // Runs the drill and prints the report; returns 0 if every check passed, 1 otherwise.
  int Run();

 private:
  enum class OpKind { kCreate, kUpdate, kDestroy };
  struct Op {
    std::string node;
    OpKind kind;
    FeatureId id;
    int64_t seq = -1;  // the node's own_change_seq right after the op; -1 unknown
  };
  struct Burst {
    const DrillAction* action;
    double start_s;
    int issued = 0;
    std::mt19937_64 rng;
  };

  double ElapsedS() const;
  bool Expired() const;
  std::vector<std::string> Expand(const std::vector<std::string>& names) const;
  std::vector<std::string> Live() const;
  std::vector<std::string> LiveNodes() const;
  std::vector<std::string> Command(const std::string& name) const;

  Result<ControlReply> Call(const std::string& name, const std::string& line,
                            int timeout_ms = 3000);
  // Reads status; records the acknowledged sequence. Empty map if the call fails.
  std::map<std::string, std::string> Status(const std::string& name);

  void StartAll();
  void RunAction(const DrillAction& a);
  void RandomOp(Burst& b);
  bool Converge(std::string& detail);
  void Check(const std::string& what, bool ok, const std::string& detail);
  void Renders();

  DrillConfig drill_;
  ExerciseConfig exercise_;
  DrillOptions options_;
  Supervisor sup_;
  std::map<std::string, std::FILE*> logs_;
  std::chrono::steady_clock::time_point start_;
  std::vector<Op> ops_;
  std::set<FeatureId> issued_ids_;
  std::vector<FeatureId> reused_ids_;
  std::set<FeatureId> alive_;                // the drill's model
  std::map<std::string, uint64_t> dropped_;  // fault_dropped per process, last seen
  std::map<std::string, int64_t> acked_;     // highest acknowledged_change_seq seen per node
  std::set<std::string> stopped_;  // killed or stopped by the drill and not restarted since
  std::vector<std::string> sanitizer_reports_;  // "name: line" of every ASan/UBSan/LSan report
  std::vector<Burst> bursts_;
  std::vector<std::string> failures_;
  std::vector<std::string> report_;
  int ops_failed_ = 0;
  bool fatal_ = false;
};

}  // namespace dt
