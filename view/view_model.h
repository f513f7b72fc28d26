// ViewModel: what the live view's page shows of an observer replica (features, their history,
// the event log, processes, vehicles) as JSON snapshots and deltas (docs/view.md "Messages").
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/replica.h"
#include "view/process_row.h"
#include "view/vehicle_source.h"

namespace dt {

// Names the exercise's members for the page ("node-1" rather than "1:1").
using MemberNames = std::map<NodeAddress, std::string>;

// One feature as the page draws it: its type's shape parameters, whether it is placed (a bridge
// overlapping a lower-ID bridge is kept but not placed), and its history.
nlohmann::json FeatureJson(FeatureId id, const Record& record);

// What a page opened now needs, copied from the model in a few milliseconds (each feature's text
// is shared, not copied) so that the view's loop waits only for the copy; the text (tens of
// megabytes at 10^5 features and 30 000 vehicles) is written from it after the lock is released
// (docs/view.md "Messages").
struct SnapshotCopy {
  uint64_t seq = 0;
  int relief_version = -1;
  std::vector<std::shared_ptr<const std::string>> features;  // each feature's JSON with history
  std::string events;                                        // a JSON array
  std::string processes;                                     // a JSON array
  std::vector<VehicleView> vehicles;
  std::vector<uint32_t> slots;  // each vehicle's slot in the binary vehicle message
  // The snapshot message: `extra`'s members (the exercise) first, then the copy's.
  std::string Text(int64_t now_ms, const nlohmann::json& extra) const;
};

class ViewModel {
 public:
  // `replica` must outlive the model. `events_kept` bounds the event log a late page receives.
  ViewModel(const Replica& replica, MemberNames names, size_t events_kept = 500);

  // A digest that differs from the exercise's this long is an event ("differs"): a change takes
  // well under this to reach every process, so a difference that lasts is a divergence the
  // process may not know of (it was fed another terrain), not a change on its way.
  static constexpr int64_t kDiffersAfterMs = 5000;

  // Looks at what changed since the last call (new changes in any log, repaired slots, process
  // rows, vehicles). Returns the delta message for the pages, or null when nothing changed: the
  // features, processes and vehicles that changed, the feature and vehicle IDs gone.
  // `now_ms` is wall-clock (epoch) milliseconds: the page measures its latency against it.
  // A vehicle is a row with its slot, [id, owner, type, x, z, heading, speed, alive, slot]. Given
  // `vehicle_frame`, the vehicles the page already knows that only moved (or died) go there
  // instead, as the binary vehicle message (view/vehicle_frame.h; empty when none moved), and the
  // JSON keeps the new ones; the two share the tick's seq, the JSON going first.
  nlohmann::json Update(int64_t now_ms, const std::vector<ProcessRow>& processes,
                        const std::vector<VehicleView>& vehicles, int relief_version,
                        std::string* vehicle_frame = nullptr);
  // Everything a page opened now needs: every live feature with its history, the event log, the
  // latest process rows and vehicles. Copy() is what the lock that orders snapshots with the
  // deltas must cover; Snapshot() is Copy().Text() read back (for tests).
  SnapshotCopy Copy() const;
  nlohmann::json Snapshot(int64_t now_ms) const;

  uint64_t seq() const { return seq_; }
  size_t feature_count() const { return features_.size(); }

 private:
  struct Event {
    int64_t t_ms = 0;
    // create update destroy breach | joined silent back diverged agrees differs matches
    std::string kind;
    std::string feature;  // "site:host:number" or empty
    std::string by;       // the author's or the process's name
    int64_t change_seq = 0;
    nlohmann::json ToJson() const;
  };
  std::string Name(NodeAddress a) const;
  // Notes one change the replica holds for the first time: history, event, feature to resend.
  void Note(const Change& c, int64_t now_ms, std::vector<Event>& events);
  // Re-reads the records of these features; removed ones go to `removed`.
  void Refresh(const std::set<FeatureId>& ids, nlohmann::json& changed, nlohmann::json& removed);
  // The replica dropped changes only it held (docs/protocol.md "Observers"): they leave the
  // history, and their slots are noted again when a change fills them.
  void ForgetDropped();
  void NoteProcesses(int64_t now_ms, const std::vector<ProcessRow>& rows,
                     std::vector<Event>& events);
  // "differs" once a reachable process's digest has differed from the exercise's for
  // kDiffersAfterMs; "matches" when it agrees again.
  void NoteDiffering(int64_t now_ms, const std::vector<ProcessRow>& rows,
                     std::vector<Event>& events);

  const Replica& replica_;
  MemberNames names_;
  size_t events_kept_;
  uint64_t seq_ = 0;
  // Per author: every change up to this one has been noted, and those noted beyond it.
  std::map<NodeAddress, int64_t> noted_upto_;
  std::map<NodeAddress, std::set<int64_t>> noted_beyond_;
  uint64_t repairs_seen_ = 0;
  uint64_t drops_seen_ = 0;
  // Live records as last sent: their fields (to tell a change), and their text with history as a
  // snapshot sends it, rebuilt when either changes so that a snapshot only shares it.
  struct HeldFeature {
    nlohmann::json fields;
    std::shared_ptr<const std::string> text;
  };
  std::map<FeatureId, HeldFeature> features_;
  std::set<FeatureId> history_changed_;  // since the last Update: their text is rebuilt
  std::map<FeatureId, std::vector<Event>> history_;
  std::vector<Event> events_;  // the last events_kept_
  std::vector<ProcessRow> processes_;
  std::set<std::string> seen_live_;  // processes seen live once: the next time they are "back"
  // Processes whose digest differs from the exercise's (the server's, else the most common), and
  // since when; `reported` once it has differed for kDiffersAfterMs and the log said so.
  struct Differing {
    int64_t since_ms = 0;
    bool reported = false;
  };
  std::map<std::string, Differing> differing_;
  // Vehicles as last sent, and the Update (counted by listings_) each was last listed in.
  struct HeldVehicle {
    VehicleView view;
    uint64_t listed_at = 0;
    uint32_t slot = 0;
  };
  std::unordered_map<std::string, HeldVehicle> vehicles_;
  // Slots of vehicles gone, used again first: the page's arrays stay as long as the most listed.
  std::vector<uint32_t> free_slots_;
  uint32_t next_slot_ = 0;
  uint64_t listings_ = 0;
  // Held features that are bridges: a bridge change re-places every bridge, and only bridges.
  std::set<FeatureId> bridges_;
  int relief_version_ = -1;
  // A Destruct of a berm by an author, so that author's next Constructs are its breach pieces.
  std::map<NodeAddress, std::pair<int64_t, FeatureId>> last_berm_destruct_;
};

}  // namespace dt
