// StatusReport: what a process answers to `status` on its control socket (its identity, protocol
// state, counters and vehicles), typed, and the one definition of that reply's text.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "pdu/pdu_type.h"
#include "pdu/validation.h"
#include "vehicle/physical_vehicle.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// The text is "key value" lines joined by '\n' (no newline after the last), in this order
// (docs/node.md "status"):
//   name, address, role, require_server, signed_on, caught_up, diverged, diverged_since_ms,
//   features, digest, own_feature_number, own_change_seq, acknowledged_change_seq, sent,
//   received, rejected, played_back, applied, ignored_stale, fault_dropped, drop_probability,
//   write_queued, write_retried, write_failed, write_given_up, voided, gave_up,
//   refused_stranger, refused_role, refused_claim, refused_lamport, refused_ground, ground_digest,
//   ground_source, ground_refused, exercise_ground_digest, rejected_<reason> for every
//   RejectReason in enum order, authenticated, auth_senders, clock_suspect_senders,
//   clock_worst_offset_ms, own_clock_suspect, own_clock_offset_ms (one line each; flags are 1 or
//   0), then the repeated lines: max_feature per origin, clock_suspect per sender whose PDUs are
//   dropped as stale, ground_mismatch per member on another ground, divergence per open difference,
//   vehicle per vehicle, then other_lines.
struct StatusReport {
  // "max_feature <site:host> <number>": the highest feature number known of an origin.
  struct MaxFeature {
    NodeAddress origin;
    int64_t number = 0;
    bool operator==(const MaxFeature&) const = default;
  };
  // "clock_suspect <site:host> offset_ms=<ms> stale=<n>": a sender whose PDUs are dropped as
  // stale now (pdu/clock_watch.h ClockSuspect).
  struct ClockSuspect {
    NodeAddress sender;
    int64_t offset_ms = 0;  // its clock minus this host's; positive: it is ahead
    uint64_t stale = 0;     // its PDUs dropped as stale since it became suspect
    bool operator==(const ClockSuspect&) const = default;
  };
  // "ground_mismatch <site:host> digest=<hex>": a member whose last MaxFeature reported another
  // ground than this process's (docs/pdu.md "Ground identity").
  struct GroundMismatch {
    NodeAddress member;
    std::string digest;
    bool operator==(const GroundMismatch&) const = default;
  };
  // "divergence <author> with <peer> changes <first>..<last>[ (not located)] since_ms <ms>": an
  // open anti-entropy difference (engine/anti_entropy.h).
  struct Divergence {
    NodeAddress author;
    NodeAddress peer;
    int64_t first_seq = 0;
    int64_t last_seq = 0;
    bool located = false;  // first_seq..last_seq are the differing slots, not a whole prefix
    int64_t since_ms = 0;
    bool operator==(const Divergence&) const = default;
  };
  // "vehicle <index> <type> x_m= z_m= y_m= heading_rad= speed_mps= on_bridge= alive= model=
  // damage=": one of the process's own vehicles (positions to 0.01 m, heading to 0.001 rad).
  struct Vehicle {
    size_t index = 0;  // what `drive <vehicle>` names
    std::string type;
    double x_m = 0.0, z_m = 0.0;
    double y_m = 0.0;  // the elevation (docs/vehicles.md "Frames")
    double heading_rad = 0.0;
    double speed_mps = 0.0;
    std::optional<FeatureId> on_bridge;  // "-" when on no bridge
    bool alive = true;
    VehicleModel model = VehicleModel::kPhysical;
    Damage damage = Damage::kNone;
    bool operator==(const Vehicle&) const = default;
  };

  std::string name;
  NodeAddress address;
  NodeRole role = NodeRole::kNode;
  bool require_server = false;  // false in an exercise without a server
  bool signed_on = false;
  bool caught_up = false;
  bool diverged = false;
  int64_t diverged_since_ms = -1;  // when the oldest open difference was found; -1: none
  uint64_t features = 0;           // live features held
  std::string digest;              // the terrain digest, hex
  int64_t own_feature_number = 0;
  int64_t own_change_seq = 0;
  int64_t acknowledged_change_seq = 0;  // what the server last reported durable of own changes
  // PDU counters (engine/replica.h Replica::Counters).
  uint64_t sent = 0, received = 0, rejected = 0, played_back = 0, applied = 0, ignored_stale = 0;
  // Receive faults (transport/faulty_transport.h).
  uint64_t fault_dropped = 0;
  double drop_probability = 0.0;
  // Write retries (transport/retrying_transport.h).
  uint64_t write_queued = 0, write_retried = 0, write_failed = 0, write_given_up = 0;
  uint64_t voided = 0, gave_up = 0;
  uint64_t refused_stranger = 0, refused_role = 0, refused_claim = 0, refused_lamport = 0;
  uint64_t refused_ground = 0;
  // Ground identity (docs/pdu.md "Ground identity"): the digest of the ground this process
  // loaded and where from (runtime/exercise_ground.h); whether it is refused for being on
  // another ground than the exercise's, and that ground's digest then ("-" otherwise).
  std::string ground_digest;
  std::string ground_source;
  bool ground_refused = false;
  std::string exercise_ground_digest = "-";
  // The bus's rejections, indexed by RejectReason: "rejected_<RejectReasonName> <n>".
  std::array<uint64_t, kRejectReasonCount> rejected_by_reason{};
  bool authenticated = false;
  uint64_t auth_senders = 0;  // senders tracked for replays, itself included
  // Clock skew (pdu/clock_watch.h): senders whose PDUs are dropped as stale now, and the suspect
  // offset of the largest magnitude, signed (0 when none).
  uint64_t clock_suspect_senders = 0;
  int64_t clock_worst_offset_ms = 0;
  // Whether this host's own clock is the likely culprit (every other sender is off alike), and
  // then by how much (this host's clock minus the exercise's; 0 when not suspect).
  bool own_clock_suspect = false;
  int64_t own_clock_offset_ms = 0;
  std::vector<MaxFeature> max_features;
  std::vector<ClockSuspect> clock_suspects;
  std::vector<GroundMismatch> ground_mismatches;
  std::vector<Divergence> divergences;
  std::vector<Vehicle> vehicles;
  // Lines whose key this reader does not know, as (key, value) in the order they came: the
  // process's own lines that follow the common ones (a node's vehicle-sharing counters, the DIS
  // gateway's) and keys added after this reader was built. Parse keeps them rather than failing,
  // so older and newer readers and writers keep working together; ToText writes them last.
  std::vector<std::pair<std::string, std::string>> other_lines;

  bool operator==(const StatusReport&) const = default;

  // The reply's text; Parse(ToText()) gives back an equal report.
  std::string ToText() const;
  // Reads a reply's text. Every single-line key above must be there once, with a value of its
  // type; repeated lines must have their shape. An Error names the key or line and its value:
  // a missing key ("no \"received\" line"), a value that does not read, a line with no space,
  // a known single key given twice. Blank lines (a trailing newline) are skipped. Never throws.
  static Result<StatusReport> Parse(std::string_view text);
};

}  // namespace dt
