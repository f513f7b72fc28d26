// ClockWatch: tells clock skew between hosts from PDUs dropped as stale, per sender, and says so.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "base/feature_id.h"

namespace dt {

// A suspect sender's line, and this host's own, is repeated at most this often while it lasts.
inline constexpr std::chrono::milliseconds kClockLogInterval{10000};
// A sender stays suspect this long after its latest stale PDU; a sender counts as agreeing with
// this host for this long after its latest accepted one. Every process sends at least every
// max_feature_period_ms (0.5 s by default), so a live sender is this quiet only in an exercise
// that sets that period above the window.
inline constexpr std::chrono::milliseconds kClockWatchWindow{10000};
// This host's own clock is blamed only when at least this many other senders disagree with it
// alike: with one, either clock may be the wrong one.
inline constexpr size_t kOwnClockMinSenders = 2;

// A sender whose PDUs arrive stamped further from this host's clock than the tolerance.
struct ClockSuspect {
  NodeAddress sender;
  // The sender's clock minus this host's, by its latest stale PDU (send time minus arrival; the
  // transit time, ms on a LAN, is in it). Positive: the sender is ahead.
  int64_t offset_ms = 0;
  uint64_t stale = 0;  // its PDUs dropped as stale since it became suspect
  bool operator==(const ClockSuspect&) const = default;
};

struct ClockReport {
  std::vector<ClockSuspect> suspects;  // in address order
  // This host's clock minus the exercise's (positive: ahead), when every other sender heard
  // disagrees with it alike (ClockWatch); nullopt when nothing points at this host.
  std::optional<int64_t> own_offset_ms;
  // The suspect offset of the largest magnitude, signed; 0 when there is no suspect.
  int64_t worst_offset_ms() const;
};

// Fed by PduAuthenticator with each PDU dropped as stale (and, while any sender is suspect, each
// accepted one), it keeps per sender the latest offset and logs (DT_LOG_WARN, rate-limited; every
// line contains log::kClockSkewMarker, the per-reason drop lines of RejectLog do not):
//   - per suspect sender, when first seen and then at most every kClockLogInterval while it
//     lasts: "PDUs from 1:3 (node-3) are stamped 45.2 s ahead of this host's clock, ...";
//   - when PDUs from every other sender heard in the last kClockWatchWindow (at least
//     kOwnClockMinSenders of them, none accepted) are stale in the same direction by amounts
//     within the tolerance of each other, that this host's own clock is probably off, instead of
//     one line per sender: "every PDU received is stamped about 45 s behind this host's clock:
//     this host's clock is probably 45 s ahead of the exercise ...";
//   - once, at info level, when a suspect sender's PDU is accepted again.
// Cheap per PDU: a lookup in a map of the suspects (a handful) and no allocation but a sender's
// first entry. Not thread-safe (as PduAuthenticator).
class ClockWatch {
 public:
  // `names`: the exercise's process names by address, for the log lines (unknown: address only).
  ClockWatch(std::chrono::milliseconds tolerance, std::map<NodeAddress, std::string> names);

  // A PDU from `sender` dropped as stale at now_ms (this host's wall clock): its send time minus
  // now_ms is offset_ms. `others_agreeing`: senders other than `sender` from which a PDU was
  // accepted within kClockWatchWindow. Never throws.
  void Stale(NodeAddress sender, int64_t offset_ms, int64_t now_ms,
             size_t others_agreeing) noexcept;
  // A PDU from `sender` was accepted at now_ms: if it was suspect, the clocks agree again.
  void Accepted(NodeAddress sender, int64_t now_ms) noexcept;

  // True while Accepted has anything to do: the authenticator calls it only then, so PDUs cost
  // no lookup here when every clock agrees.
  bool watching() const { return !suspects_.empty() || own_warned_; }
  // The suspects heard within kClockWatchWindow of now_ms and the verdict on this host's clock;
  // `agreeing`: senders from which a PDU was accepted within kClockWatchWindow.
  ClockReport Report(int64_t now_ms, size_t agreeing) const;
  // Warning lines written so far (the rate limit's effect, for tests).
  uint64_t lines_logged() const { return lines_logged_; }

 private:
  struct Suspect {
    bool active = false;  // stale PDUs since the latest accepted one
    int64_t offset_ms = 0;
    uint64_t stale = 0;  // since it became active
    int64_t last_stale_ms = 0;
    std::optional<int64_t> last_logged_ms;
    bool warned = false;  // a warning was logged since it last became active: say when it ends
  };

  // This host's offset from the others', or nullopt (see the class comment).
  std::optional<int64_t> OwnOffset(int64_t now_ms, size_t agreeing) const;
  // "1:3 (node-3)", or "1:3" for an address the exercise does not name.
  std::string Describe(NodeAddress a) const;
  void LogOwn(int64_t own_offset_ms, int64_t now_ms);
  // Drops the entries of senders heard from neither way for kClockWatchWindow.
  void Sweep(int64_t now_ms);

  int64_t tolerance_ms_;
  std::map<NodeAddress, std::string> names_;
  std::map<NodeAddress, Suspect> suspects_;
  std::optional<int64_t> own_logged_ms_;
  bool own_warned_ = false;  // this host's clock was blamed and no PDU was accepted since
  uint64_t lines_logged_ = 0;
};

}  // namespace dt
