// Replica: one participant's copy of the exercise's terrain and the protocol that keeps it equal
// to everyone else's (docs/protocol.md).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "base/feature_id.h"
#include "base/growing_arena.h"
#include "base/result.h"
#include "dtpdu/max_feature_t.hpp"
#include "dtpdu/playback_t.hpp"
#include "engine/anti_entropy.h"
#include "engine/change.h"
#include "engine/change_log.h"
#include "engine/change_store.h"
#include "engine/id_reservation.h"
#include "engine/playback_scheduler.h"
#include "engine/record_store.h"
#include "pdu/pdu_type.h"
#include "terrain/base_ground.h"
#include "terrain/feature_params.h"
#include "terrain/height_grid.h"
#include "terrain/terrain.h"
#include "terrain/terrain_digest.h"
#include "transport/pdu_bus.h"

namespace dt {

// NodeRole (kNode, kServer, kStandby) is pdu/pdu_type.h's: it travels in MaxFeature. A replica
// with role kObserver (a live view) holds the terrain, creates nothing and is not counted: it
// sends no MaxFeature and no summaries, answers no playback, and its peers never ask it nor wait
// for it (docs/protocol.md, "Observers").

struct ReplicaConfig {
  NodeAddress address;
  NodeRole role = NodeRole::kNode;
  int max_feature_period_ms = 500;
  int silence_ms = 2000;  // no PDU from a node for this long: it is gone
  int playback_retry_ms =
      1000;                   // a request unanswered this long is sent again (then to the server)
  int playback_window = 256;  // changes outstanding per author
  // The most changes one playback request asks for when round trips are long (a WAN): a
  // catch-up's window grows from playback_window up to this (docs/protocol.md, "Recovering what
  // was missed"). At or below playback_window: a fixed window.
  int playback_window_max = 8192;
  // A summary of the logs held every period, so slots held differently are found and repaired
  // (docs/protocol.md, "Anti-entropy"); 0: off.
  int anti_entropy_period_ms = 1000;
  // A gap in a silent author's log that no live replica fills for this long is given up on: the
  // slot's authority fills it with voids, so no one waits for ever (docs/protocol.md, "Lost
  // changes"). 0: never. Must exceed the time a crashed node takes to restart and void its own.
  int gap_give_up_ms = 30000;
  // A node signs on only once a server (or standby) has told it its own last numbers. False: an
  // exercise without a server; the node signs on after silence_ms with whatever it heard.
  bool require_server = true;
  // A server or standby: every accepted change goes here, one batch per Tick. Not owned; must
  // outlive the replica. Null for nodes.
  ChangeStore* store = nullptr;
  // A node: where it reserves feature numbers before issuing them, so a restart never reissues
  // one (docs/protocol.md, "No ID issued twice"). Not owned; must outlive the replica. Null: the
  // number is only skipped by a window on sign-on (no guarantee if every other replica is down).
  IdReservation* ids = nullptr;
  // The exercise's members and their roles (from the exercise file). PDUs from any other sender,
  // changes by any other author and role claims that disagree are refused and counted. Empty:
  // every sender is believed (unit tests and benchmarks only).
  std::map<NodeAddress, NodeRole> members;
  // Where this replica's ground came from ("ground_file /x/y.dtt", "random seed 7 ..."), named
  // with its digest when a member on another ground is refused (docs/pdu.md "Ground identity").
  std::string ground_source = "the given ground";
  // The digest of the ground given, base features included (ComputeDigest of it), when the caller
  // holds it already (a ground cache's header, a benchmark restarting replicas on one ground):
  // spares digesting every post again at start. Empty: computed here. Pass only a digest computed
  // of exactly this ground: a wrong one would hide a differing ground from its peers.
  std::optional<TerrainDigest> ground_digest;
};

// A received Lamport clock more than this far ahead of the receiver's is refused: a clock that
// jumped by 2^32 changes is a broken or hostile peer, and accepting it would let one PDU push every
// clock towards overflow (docs/protocol.md, "Rules for what is believed").
inline constexpr uint64_t kMaxLamportLead = uint64_t{1} << 32;
// No clock reaches this: 2^62 leaves room for every lead above without overflow.
inline constexpr uint64_t kMaxLamport = uint64_t{1} << 62;

class Replica {
 public:
  // Subscribes to all PDU types on `bus`. A replica with a store first loads every stored change
  // (Load() reports a failure). Throws std::invalid_argument for a bad config (values named).
  Replica(ReplicaConfig config, HeightGrid ground, PduBus& bus);
  // On a base ground with features every member has from the start (a saved terrain): they are
  // in the terrain and the ground's digest, and are no records (engine/record_store.h).
  Replica(ReplicaConfig config, BaseGround ground, PduBus& bus);
  ~Replica();
  Replica(const Replica&) = delete;
  Replica& operator=(const Replica&) = delete;

  // Commands. A bad command (unknown ID, invalid parameters, destroyed feature, a feature that
  // cannot be placed, not signed on yet) returns an Error and changes nothing.
  Result<FeatureId> Create(const FeatureParams& params);     // next own number; Construct
  Status Modify(FeatureId id, const FeatureParams& params);  // Update
  Status Destroy(FeatureId id);                              // Destruct
  // Destruct of the berm plus a Construct per remaining piece; returns the pieces' IDs.
  Result<std::vector<FeatureId>> Breach(FeatureId berm, double gap_start_m, double gap_width_m);
  // Issues an Update of every feature of `terrain` under its own ID (server import of a terrain
  // file). The ground must equal this replica's. Refused as a whole if any feature is refused.
  Status Import(const Terrain& terrain);

  // Starts (or restarts) the protocol: asks the server for this node's own last feature number
  // and change sequence, and everyone for their maxima.
  void SignOn(int64_t now_ms);
  // MaxFeature period, playback pacing and retries, silence detection, and for a store the batch
  // commit of what was accepted since the last Tick.
  void Tick(int64_t now_ms);
  // For a store: commits what was accepted since the last Tick now (shutdown). Ok without one.
  Status Flush();

  const Terrain& terrain() const { return records_.terrain(); }
  std::string Digest() const;  // terrain digest (terrain_digest.h), hex
  bool signed_on() const { return signed_on_; }
  bool caught_up() const;  // no known gap for any author, nothing outstanding, not diverged
  // A peer holds another change in a slot this replica holds (docs/protocol.md, "Anti-entropy"):
  // since when (the Tick time it was found at; -1 when not diverged), and with whom in which
  // author's log, which changes.
  bool diverged() const { return anti_entropy_->diverged(); }
  int64_t diverged_since_ms() const { return anti_entropy_->diverged_since_ms(); }
  std::vector<AntiEntropy::Divergence> divergences() const { return anti_entropy_->divergences(); }
  const AntiEntropy& anti_entropy() const { return *anti_entropy_; }
  AntiEntropy& anti_entropy() { return *anti_entropy_; }
  const ReplicaConfig& config() const { return config_; }

  // Ground identity (docs/pdu.md "Ground identity"). The digest of the ground this replica
  // loaded (its base ground, before any change), sent in every MaxFeature.
  const TerrainDigest& ground_digest() const { return ground_digest_; }
  // This replica heard the exercise's ground (the server's; the standby's while no server is
  // heard on this replica's ground) and it is another: it takes no part, for good.
  bool ground_refused() const { return exercise_ground_.has_value(); }
  // The exercise's ground when refused, and who reported it.
  std::optional<TerrainDigest> exercise_ground_digest() const { return exercise_ground_; }
  NodeAddress exercise_ground_reporter() const { return exercise_ground_reporter_; }
  // Members whose last MaxFeature reported another ground than this replica's, with it.
  std::map<NodeAddress, TerrainDigest> ground_mismatches() const;

  struct Counters {
    uint64_t sent = 0, received = 0, rejected = 0, played_back = 0, applied = 0, ignored_stale = 0,
             voided = 0;
    // Sequences of a silent author's log no live replica held, voided by this replica as the
    // slot's authority after gap_give_up_ms (docs/protocol.md, "Lost changes").
    uint64_t gave_up = 0;
    // Refused by the protocol's rules (docs/protocol.md, "Rules for what is believed"): a sender
    // or author that is no member, a role claim that disagrees with the exercise file, a claim
    // about a node's counters from someone who may not make it (or beyond what it can be), a
    // Lamport clock too far ahead.
    uint64_t refused_stranger = 0, refused_role = 0, refused_claim = 0, refused_lamport = 0;
    // PDUs from a member on another ground, and everything while this replica is itself refused
    // (docs/pdu.md "Ground identity").
    uint64_t refused_ground = 0;
  };
  Counters counters() const;
  // When this replica last heard a PDU from a member (its Tick time); -1: never (observers are
  // never heard: they are not peers).
  int64_t last_heard_ms(NodeAddress peer) const {
    auto it = peers_.find(peer);
    return it == peers_.end() ? -1 : it->second.last_heard_ms;
  }
  // Highest feature number known per origin (own included).
  std::map<NodeAddress, int64_t> max_feature_known() const;
  // What the server last reported durable for this node's change log.
  int64_t acknowledged_change_seq() const { return acknowledged_change_seq_; }
  // This node's last issued change sequence and feature number.
  int64_t own_change_seq() const { return own_change_seq_; }
  int64_t own_feature_number() const { return own_feature_number_; }
  // Live features (records not destroyed), placed or not.
  size_t live_feature_count() const { return records_.live_count(); }
  const RecordStore& records() const { return records_; }
  // Change tracking of the records (RecordStore::TrackTouched, TakeTouched).
  void TrackTouchedFeatures() { records_.TrackTouched(); }
  std::vector<FeatureId> TakeTouchedFeatures() { return records_.TakeTouched(); }
  // The changes this replica holds from one author; null if none.
  const ChangeLog* log(NodeAddress author) const {
    auto it = logs_.find(author);
    return it == logs_.end() ? nullptr : &it->second;
  }
  // Gap-free point of each author's log as this replica holds it.
  std::map<NodeAddress, int64_t> contiguous_change_seq() const;
  // For a store: the gap-free point per author that the store holds (committed).
  std::map<NodeAddress, int64_t> durable_change_seq() const { return durable_; }
  // Result of loading the store at construction (Ok without a store).
  const Status& load_status() const { return load_status_; }
  // Result of the last store commit (Ok without a store).
  const Status& store_status() const { return store_status_; }

 private:
  struct Peer {
    NodeRole role = NodeRole::kNode;
    int64_t last_heard_ms = -1;
    int64_t reported_max_change_seq = 0;
    int64_t reported_max_feature = 0;
  };

  Status CheckSignedOn(int64_t changes) const;
  Change NewChange(ChangeKind kind, FeatureId id, const FeatureParams& params);
  void Issue(const Change& change);
  // Logs and applies a change from anywhere; false if already held.
  bool Accept(const Change& change, bool from_store);
  void Publish(const Change& change, std::optional<NodeAddress> playback_for);
  void HeardFrom(NodeAddress sender, std::optional<NodeRole> role);
  // Membership and clock rules for a received change; false (and counted) if it is refused.
  bool Admits(NodeAddress sender, NodeAddress author, uint64_t lamport);
  bool AdmitsSender(NodeAddress sender);
  // A role claim that disagrees with the exercise file is refused; `what` names the PDU.
  bool AdmitsRole(NodeAddress sender, NodeRole role, std::string_view what);
  bool AdmitsClock(NodeAddress sender, uint64_t lamport);
  // A MaxFeature's ground: refused (and counted) when it is not this replica's; a server's other
  // ground refuses this replica itself.
  bool AdmitsGround(NodeAddress sender, NodeRole role, const dtpdu::max_feature_t& pdu);
  // Counts a refusal and logs it, at most one line a second.
  void Refused(uint64_t& counter, const std::string& what);
  void ClaimAboutSelf(NodeAddress sender, NodeRole role, const dtpdu::max_feature_t& pdu);
  // A peer's anti-entropy summary shows it holds `author`'s changes up to `max_held`.
  void HeldBeyond(NodeAddress peer, NodeAddress author, int64_t max_held);
  void CompleteSignOn();
  bool observer() const { return config_.role == NodeRole::kObserver; }
  bool IsMember(NodeAddress a) const {
    return config_.members.empty() || config_.members.count(a) != 0;
  }
  // The configured role of a member (the claimed one when there is no membership list).
  NodeRole RoleOf(NodeAddress a, NodeRole claimed) const;
  // Reserves feature numbers up to `number` (and a window beyond) before one is issued.
  Status ReserveFeatureNumbers(int64_t number);
  void ObserveLamport(uint64_t lamport);
  // The log of `author`'s changes, made empty (in log_memory_) if this is the first word of it.
  ChangeLog& LogOf(NodeAddress author) {
    return logs_.try_emplace(author, &log_memory_).first->second;
  }

  void OnConstruct(const dtpdu::construct_t& pdu);
  void OnEarthMove(const dtpdu::earth_move_t& pdu);
  void OnUpdate(const dtpdu::update_t& pdu);
  void OnDestruct(const dtpdu::destruct_t& pdu);
  void OnMaxFeature(const dtpdu::max_feature_t& pdu);
  void OnPlayback(const dtpdu::playback_t& pdu);

  void SendReports();
  void SendReport(NodeAddress subject, bool sign_on, bool answer = false);
  void AnswerPlayback(const dtpdu::playback_t& request);
  void RequestMissing();
  // Sends the playback request the scheduler wants now for this author's log, if any.
  void RequestFor(NodeAddress author, const ChangeLog& log);
  void ForgetSilentReporters();
  // docs/protocol.md, "Lost changes" (engine/replica_voids.cc).
  void VoidLostOwnChanges();
  void GiveUpOnGoneAuthors();
  // Whether voids for start..end can be numbered (numbers left, reserved); logs why not.
  bool CanVoid(int64_t start, int64_t end);
  // Fills start..end of `author`'s log with voids: Destructs of fresh numbers of this replica's.
  void IssueVoids(NodeAddress author, int64_t start, int64_t end);
  // A live server or standby claims to hold `seq` of this log (its durable gap-free point).
  bool HeldByLiveServer(const ChangeLog& log, int64_t seq) const;
  void Commit();
  // Whom to ask for an author's changes, in order of preference.
  std::vector<NodeAddress> Candidates(NodeAddress author) const;
  bool IsSilent(NodeAddress node) const;
  bool AnswersForServer() const;
  void NoteOwn(const Change& change);

  ReplicaConfig config_;
  PduBus& bus_;
  RecordStore records_;
  // Digest() every status or relief period would read the whole ground each time; this keeps
  // the ground's hash state and the last digest, keyed on the terrain's stamps.
  mutable TerrainDigester digester_;
  TerrainDigest ground_digest_;
  std::map<NodeAddress, TerrainDigest> peer_grounds_;  // per member, its last reported ground
  std::optional<TerrainDigest> exercise_ground_;       // set when this replica is refused
  NodeAddress exercise_ground_reporter_;
  GrowingArena log_memory_;  // before logs_: their slots live in it
  std::map<NodeAddress, ChangeLog> logs_;
  PlaybackScheduler scheduler_;
  std::map<NodeAddress, Peer> peers_;
  std::map<NodeAddress, int64_t> max_feature_;  // per origin
  std::map<NodeAddress, int64_t> durable_;      // store only
  std::vector<Change> pending_store_;
  Status load_status_;
  Status store_status_;
  uint64_t lamport_ = 0;
  int64_t own_change_seq_ = 0;
  int64_t own_feature_number_ = 0;
  int64_t acknowledged_change_seq_ = 0;
  int64_t reserved_feature_number_ = 0;  // with config_.ids: numbers up to this are reserved
  bool had_reservation_ = false;         // an earlier incarnation's reservation was loaded
  // Peer nodes' answers to this node's sign-on: the highest change of this node each holds;
  // applied when the sign-on completes, bounded by what the server acknowledged.
  struct PeerClaim {
    int64_t change_seq = 0;
    int64_t feature_number = 0;
  };
  std::map<NodeAddress, PeerClaim> sign_on_peer_claims_;
  bool signed_on_ = false;
  bool signing_on_ = false;
  bool server_answered_ = false;
  int64_t sign_on_started_ms_ = 0;
  int64_t sign_on_sent_ms_ = 0;
  std::set<NodeAddress> sign_on_requests_;
  std::set<NodeAddress> sign_on_answered_by_;
  std::set<NodeAddress> sign_on_expected_;  // answered in the next Tick, after the commit
  int64_t now_ms_ = 0;
  int64_t last_report_ms_ = -1;
  int64_t last_refusal_log_ms_ = -1;
  uint64_t refusals_since_log_ = 0;
  Counters counters_;
  // Per author: the first gap of its log and since when it has not moved.
  struct GapStuck {
    int64_t start = 0;
    int64_t since_ms = 0;
  };
  std::map<NodeAddress, GapStuck> gap_stuck_;
  std::unique_ptr<AntiEntropy> anti_entropy_;  // made last: its handlers run after ours
};

}  // namespace dt
