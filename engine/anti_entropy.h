// AntiEntropy: replicas compare summaries of the change logs they hold, locate the slots they hold
// differently and repair them by one rule (docs/protocol.md, "Anti-entropy").
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "base/feature_id.h"
#include "base/result.h"
#include "dtpdu/anti_entropy_t.hpp"
#include "engine/change.h"
#include "engine/change_log.h"
#include "engine/change_store.h"
#include "engine/prefix_hashes.h"
#include "engine/record_store.h"
#include "pdu/pdu_type.h"
#include "transport/pdu_bus.h"

namespace dt {

struct AntiEntropyConfig {
  NodeAddress self;
  NodeRole role = NodeRole::kNode;
  int period_ms = 1000;   // a summary every period; 0: anti-entropy is off
  int retry_ms = 1000;    // a request unanswered this long is sent again, at most kMaxAttempts
  int silence_ms = 2000;  // a peer unheard for max(silence_ms, 3 periods) is forgotten
  ChangeStore* store = nullptr;  // a server or standby: repaired slots are stored here
  // An observer drops the changes it holds beyond what every live replica holds once the author's
  // own summary says it holds less, or once none has reported them for this long (the replica's
  // gap_give_up_ms; docs/protocol.md, "Observers"). 0: only on the author's word.
  int drop_unreported_ms = 0;
};

// Works on its replica's logs and records (which must outlive it) and speaks AntiEntropy PDUs
// on the replica's bus. Every `period_ms` it multicasts, per author, the gap-free point and the
// hash of the log prefix up to it (PrefixHashes). A receiver holding that prefix compares it with
// its own; on a difference it asks the sender for the hashes of kAntiEntropyBuckets buckets of
// the prefix, recurses into the buckets that differ down to single slots, fetches the sender's
// copies of those and has the sender fetch its own (an exchange), and each side keeps the copy
// the repair rule (engine/repair_rule.h) picks. A replaced slot is re-applied to the records (so
// terrain and digest follow) and, with a store, stored in place of the old copy.
class AntiEntropy {
 public:
  using Logs = std::map<NodeAddress, ChangeLog>;
  // Sends a held change as a playback for `requester` (the replica's Publish).
  using PublishCopy = std::function<void(const Change& change, NodeAddress requester)>;
  // Told after a held change was replaced, once the log, records and store follow.
  using Replaced = std::function<void(const Change& old_copy, const Change& new_copy)>;
  // The replica's rules for what is believed (docs/protocol.md "Rules for what is believed"),
  // so anti-entropy trusts no more than live traffic does: whether an AntiEntropy PDU from
  // `sender` claiming `role` is heard at all, and whether `sender`'s copy of a change may be kept.
  struct Admission {
    std::function<bool(NodeAddress sender, NodeRole role)> peer;
    std::function<bool(NodeAddress sender, const Change& copy)> copy;
  };

  // Told when a peer's summary shows it holds a change of `author` beyond every one this replica
  // knows of (up to `max_held`): changes held beyond a gap whose author is gone reach no one
  // otherwise (the replica treats it as a claim to fetch, docs/protocol.md "Lost changes").
  using HeldBeyond = std::function<void(NodeAddress peer, NodeAddress author, int64_t max_held)>;

  AntiEntropy(AntiEntropyConfig config, Logs& logs, RecordStore& records, PduBus& bus,
              PublishCopy publish, Replaced replaced, Admission admission = {},
              HeldBeyond held_beyond = {});
  AntiEntropy(const AntiEntropy&) = delete;
  AntiEntropy& operator=(const AntiEntropy&) = delete;

  // Summaries, retries, forgetting silent peers, a store write that failed.
  void Tick(int64_t now_ms);

  // A difference with one peer in one author's log, from when it was found until a summary of
  // that peer agrees again (or the peer falls silent).
  struct Divergence {
    NodeAddress author;
    NodeAddress peer;
    int64_t first_seq = 0;  // the slots known to differ lie in first_seq..last_seq
    int64_t last_seq = 0;
    int64_t since_ms = 0;  // the Tick time it was found at
    bool located = false;  // first_seq..last_seq are the differing slots, not a whole prefix
  };
  bool diverged() const { return !divergences_.empty(); }
  // When the oldest difference still open was found; -1 when there is none.
  int64_t diverged_since_ms() const;
  std::vector<Divergence> divergences() const;

  struct Stats {
    uint64_t summaries_sent = 0, summaries_received = 0, hash_requests_sent = 0,
             hash_answers_sent = 0, copy_requests_sent = 0, copies_sent = 0, differences_found = 0,
             slots_repaired = 0, sessions_given_up = 0;
    // An observer's changes no other replica holds, taken out of its logs (docs/protocol.md,
    // "Observers"); the records of their features are rebuilt, as for a repaired slot.
    uint64_t slots_dropped = 0;
    uint64_t bytes_sent = 0, bytes_received = 0;  // AntiEntropy PDUs only (not the copies)
  };
  const Stats& stats() const { return stats_; }

  // Puts `change` in its slot in place of the copy held, in memory only (a store keeps its
  // copy), as a corruption would: for tests and drills. Error if the slot is not held.
  Status Overwrite(const Change& change);

  // Requests outstanding per session; more wait their turn.
  static constexpr size_t kMaxOutstanding = 16;
  // Sends of one request before the session is given up (the next summary starts it again).
  static constexpr int kMaxAttempts = 3;

 private:
  using Key = std::pair<NodeAddress, NodeAddress>;  // (peer, author)
  struct Ask {
    int64_t end = 0;
    int64_t sent_ms = 0;
    int attempts = 1;
  };
  // Locating and repairing the difference with one peer in one author's log.
  struct Session {
    std::deque<std::pair<int64_t, int64_t>> to_ask;  // ranges whose bucket hashes are wanted
    std::map<int64_t, Ask> hash_asks;                // by start
    std::map<int64_t, Ask> copy_asks;                // by start
    std::set<int64_t> differing;                     // slots located
    std::map<int64_t, Change> received;              // the peer's copies, by seq
    bool located = false;   // location is over (or there was none: an exchange)
    bool exchange = false;  // our copy requests ask the peer to fetch ours in turn
  };

  void OnPdu(const dtpdu::anti_entropy_t& pdu);
  template <typename ChangePdu>
  void OnCopy(const ChangePdu& pdu);
  void OnSummary(NodeAddress peer, const dtpdu::anti_entropy_t& pdu);
  void OnHashRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end);
  void OnHashAnswer(NodeAddress peer, const dtpdu::anti_entropy_t& pdu);
  void OnCopyRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end,
                     bool exchange);
  void OnCopies(NodeAddress peer, const dtpdu::anti_entropy_t& pdu);
  // How long a peer (or an author in its summaries) may stay unheard before it is forgotten.
  int64_t ForgetMs() const;

  void SendSummaries();
  void Send(dtpdu::anti_entropy_t pdu);
  dtpdu::anti_entropy_t Addressed(AntiEntropyKind kind, NodeAddress target, NodeAddress author,
                                  int64_t start, int64_t end) const;
  void SendHashRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end);
  void SendCopyRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end,
                       bool exchange);

  void Agrees(const Key& key);
  void Differs(const Key& key, int64_t upto);
  // Sends what the session may send now; ends it when nothing is left. `key` may be gone after.
  void Pump(const Key& key);
  void EndSession(const Key& key);
  void RetryAsks();
  void ForgetSilentPeers();

  // The slot's authority (engine/repair_rule.h) among this replica and the live peers whose last
  // summary shows the slot held.
  std::optional<NodeAddress> Authority(NodeAddress author, int64_t seq) const;
  // Applies the repair rule to the peer's copy of a slot held here.
  void Decide(NodeAddress peer, const Change& theirs);
  // The log, its prefix hashes and the records take `change` in place of the held copy.
  void Put(const Change& old_copy, const Change& change);
  // The records of these features applied again from every change of them held.
  void RebuildRecords(const std::vector<FeatureId>& ids);
  void FlushStore();

  // An observer's changes beyond what every other replica holds (engine/anti_entropy_drop.cc).
  void DropWhatOnlyThisHolds();
  // The highest change of `author` a live peer's summary or a live claim says is held elsewhere.
  int64_t HeldElsewhere(NodeAddress author, const ChangeLog& log) const;
  // Takes the changes above `keep_upto` out of `author`'s log; `why` goes to the log line.
  void Drop(NodeAddress author, int64_t keep_upto, const std::string& why);
  // The prefix hashes of a held author's log, extended to its gap-free point.
  PrefixHashes& Prefix(NodeAddress author);
  const ChangeLog* FindLog(NodeAddress author) const;

  AntiEntropyConfig config_;
  Logs& logs_;
  RecordStore& records_;
  PduBus& bus_;
  PublishCopy publish_;
  Replaced replaced_;
  Admission admission_;
  HeldBeyond held_beyond_;
  std::map<NodeAddress, PrefixHashes> prefixes_;
  std::map<Key, Session> sessions_;
  std::map<Key, Divergence> divergences_;
  std::set<Key> from_exchange_;  // divergences a peer told us of: closed with their session
  // A live peer as its AntiEntropy PDUs show it.
  struct PeerView {
    int64_t last_heard_ms = 0;
    NodeRole role = NodeRole::kNode;
    struct Held {
      int64_t seq = 0;       // the gap-free point its last summary gave
      int64_t seen_ms = 0;   // when; an author missing from its summaries for long is dropped
      int64_t max_held = 0;  // the highest change it held then, maybe beyond a gap
    };
    std::map<NodeAddress, Held> gap_free;  // per author
  };
  std::map<NodeAddress, PeerView> peers_;
  std::vector<Change> pending_store_;  // repaired slots the store has not taken yet
  // An observer, per author: it has held more than every other replica since since_ms, its
  // highest change being `held` then (a new change restarts the clock).
  struct Beyond {
    int64_t held = 0;
    int64_t since_ms = 0;
  };
  std::map<NodeAddress, Beyond> beyond_;
  bool store_failing_ = false;
  int64_t now_ms_ = 0;
  int64_t last_summary_ms_ = -1;
  Stats stats_;
};

}  // namespace dt
