// DrillRunner: runs a drill against a real exercise (processes, sockets, transport) and checks
// the protocol's guarantee at the end (docs/launcher.md "Drills").
#pragma once

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "launcher/chaos_plan.h"
#include "launcher/drill_config.h"
#include "launcher/exercise_commands.h"
#include "launcher/host_network.h"
#include "launcher/supervisor.h"
#include "runtime/control_protocol.h"
#include "runtime/exercise_config.h"
#include "runtime/status_report.h"
#include "runtime/vehicle_listing.h"
#include "terrain/feature_params.h"

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
    int incarnation = 0;  // which start of the node issued it (1 = the first)
    OpKind kind = OpKind::kCreate;
    FeatureId id;
    int64_t seq = -1;  // the node's own_change_seq right after the op; -1 unknown
  };
  struct Burst {
    const DrillAction* action;
    double start_s;
    int issued = 0;
    std::mt19937_64 rng;
  };
  // A running chaos action (drill_chaos.cc).
  struct Chaos {
    const DrillAction* action;
    double start_s;
    std::vector<ChaosRound> plan;
    size_t next = 0;                        // the next round of the plan
    std::map<std::string, double> down;     // killed by it: name -> restart time (elapsed s)
    std::map<std::string, double> waiting;  // restarted, not READY yet: name -> restart time
  };
  // A running sample_vehicles action (drill_vehicles.cc).
  struct Sampling {
    const DrillAction* action = nullptr;
    double start_s = 0.0;
    double next_s = 0.0;  // the next round
    int rounds = 0;
    std::map<std::string, std::pair<int, int>> error_samples;  // target -> (within, all)
    double worst_error_m = 0.0;
    double max_tilt_deg = -1.0;  // of the owner's remote vehicles on the targets; -1 none seen
    std::string max_tilt_where;
    std::vector<std::string> errors;  // replies that failed or did not parse (the first few)
    std::FILE* csv = nullptr;         // <run_dir>/vehicle-samples-<k>.csv: the error samples
  };
  using Incarnation = std::pair<std::string, int>;
  // Long enough that a node held up for seconds still answers: an unanswered command's outcome
  // is unknown and weakens the checks.
  static constexpr int kOpTimeoutMs = 10000;

  double ElapsedS() const;
  bool Expired() const;
  std::vector<std::string> Expand(const std::vector<std::string>& names) const;
  std::vector<std::string> Live() const;
  std::vector<std::string> LiveNodes() const;
  std::vector<std::string> Command(const std::string& name) const;
  void HealLinks();  // hosts mode: every link up again

  Result<ControlReply> Call(const std::string& name, const std::string& line,
                            int timeout_ms = 3000);
  // Reads status; records the acknowledged sequence. An Error if the call fails, is refused, or
  // the reply does not read.
  Result<StatusReport> Status(const std::string& name);

  // Starts (or restarts) a process: a new incarnation, no longer counted as stopped.
  void StartProcess(const std::string& name);
  // SIGKILL, wait for the exit, and check that the kill (not a crash before it) ended it.
  void KillNow(const std::string& name);
  void StartAll();
  void RunAction(const DrillAction& a);

  // drill_ops.cc: random operations and the drill's model of the features it made.
  void RandomOp(Burst& b);
  // Records a feature command a node accepted (create, update, destroy, breach): the IDs it
  // issued, the model, and the operations with the node's change sequence after them.
  void RecordAccepted(const std::string& node, const std::string& line, const ControlReply& reply);
  // A feature command with no reply in time: its outcome is unknown (left out of the checks).
  void RecordUnanswered(const std::string& node, const std::string& line, const std::string& error);
  void NoteIssued(const FeatureId& id);

  // drill_chaos.cc: the chaos action.
  void StartChaos(const DrillAction& a);
  // Restarts, readiness, due rounds; lowers next_due_s to its next event. False once finished.
  bool ChaosStep(Chaos& c, double& next_due_s);
  void KillRound(Chaos& c, size_t index);

  // drill_vehicles.cc: the vehicle actions (docs/launcher.md "Vehicle actions").
  std::vector<std::string> VehicleTargets(const DrillAction& a) const;
  Result<std::vector<ListedVehicle>> Vehicles(const std::string& node);
  // Blocks (like a restart) until the targets hold the owner's vehicles, or none of them.
  void VehiclesSeen(const DrillAction& a);
  // One round when due; lowers next_due_s to the next. False once finished (checked).
  bool SampleStep(Sampling& s, double& next_due_s);
  void SampleRound(Sampling& s);
  void FinishSampling(Sampling& s);
  // What a blocking action's wait does: due sampling rounds, then the children's output for up
  // to timeout_ms (less when a round falls due sooner). True if interrupted.
  bool PollBeside(int timeout_ms);
  // Blocks until the owner's vehicle is alive inside the action's box (within_s).
  void VehicleReaches(const DrillAction& a);

  // drill_digest_mark.cc: the digest action.
  void DigestMark(const DrillAction& a);

  bool Converge(std::string& detail);
  // One round of status replies: true when every live process holds one digest, is caught up,
  // and every node's own changes are acknowledged; `detail` lists the digests (and, when not,
  // what is missing).
  bool AgreeOnce(std::string& detail);
  // Checks 2-4 (docs/launcher.md "Checks") against the features a live process holds.
  void CheckFeatures();
  // The live feature IDs a process holds (empty if the call fails).
  std::set<FeatureId> Features(const std::string& name);
  // After unequal digests: which feature IDs each live process holds beside the first's.
  void ReportDivergence();
  void Check(const std::string& what, bool ok, const std::string& detail);
  void Renders();

  DrillConfig drill_;
  ExerciseConfig exercise_;
  DrillOptions options_;
  // Hosts mode: the namespaces the processes run in. Declared before sup_ so that it outlives
  // the children (destroyed after them). Null otherwise.
  std::unique_ptr<HostNetwork> hosts_;
  std::string carrier_url_;  // passed to every process as --transport; empty: the exercise's
  Supervisor sup_;
  std::map<std::string, std::FILE*> logs_;
  std::chrono::steady_clock::time_point start_;
  std::vector<Op> ops_;
  std::set<FeatureId> issued_ids_;
  std::vector<FeatureId> reused_ids_;
  std::set<FeatureId> alive_;                 // the drill's model
  std::set<FeatureId> maybe_gone_;            // targets of unanswered destroys and breaches
  std::map<FeatureId, FeatureParams> berms_;  // live berms the drill made (breach candidates)
  std::map<std::string, uint64_t> dropped_;   // fault_dropped per process, last seen
  // Highest acknowledged_change_seq seen per node incarnation: a new incarnation may reuse the
  // sequence of a change its predecessor lost, so only the issuing incarnation's ack counts.
  std::map<Incarnation, int64_t> acked_;
  std::map<std::string, int> incarnation_;  // starts per process
  std::set<std::string> stopped_;  // killed or stopped by the drill and not restarted since
  std::vector<std::string> sanitizer_reports_;  // "name: line" of every ASan/UBSan/LSan report
  std::vector<Burst> bursts_;
  std::vector<Chaos> chaos_;
  std::vector<Sampling> samplings_;
  std::map<std::string, std::string> kept_ids_;  // command `as` name -> the ID it gave
  struct Mark {
    std::string digest;
    double at_s = 0.0;
  };
  std::map<std::string, Mark> marks_;  // digest action: mark -> the digest first agreed on
  int kills_ = 0;                      // SIGKILLs sent by the drill (kill actions and chaos)
  int restarts_ = 0;                   // starts after the first
  bool digests_equal_ = false;         // at the last convergence poll
  std::map<std::string, std::string> last_digests_;  // per live process, at that poll
  size_t acked_ops_ = 0;   // operations found acknowledged (CheckFeatures)
  size_t lost_count_ = 0;  // acknowledged operations found undone (CheckFeatures)
  std::vector<std::string> failures_;
  std::vector<std::string> report_;
  int ops_failed_ = 0;                   // refused by the node
  int ops_unanswered_ = 0;               // no reply within kOpTimeoutMs
  std::vector<std::string> unanswered_;  // the first few, for the report
  double slowest_reply_s_ = 0.0;         // of random operations
  std::string slowest_reply_;
  bool fatal_ = false;
};

}  // namespace dt
