// PlaybackScheduler: which missing ranges to request, from whom and when, per author, and how
// many changes a request covers.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "base/feature_id.h"
#include "engine/change_log.h"

namespace dt {

// One request outstanding per author. A request that gets no progress within retry_ms, or whose
// answer leaves the gap open, is sent again to the next candidate (candidates are ordered by the
// caller: the author first, then the servers, then any other live replica).
//
// A request covers at most the author's window, which adapts between `window` and `max_window`
// (docs/protocol.md, "Recovering what was missed"): with one request outstanding a catch-up moves
// one window per round trip, so across a WAN (100 ms) a fixed window of 256 caps it at 2.5 k
// changes/s whatever the carrier could take. After each answer that filled its whole range the
// window is set from what that answer showed: its latency (request to first change, less one
// tick of the replica's clock, which is all a LAN's round trip shows) and its rate (changes per
// ms from first change to the marker). Latency to hide: the window becomes four latencies' worth
// of changes at that rate (at most doubling per answer, and small enough to arrive within half of
// retry_ms); none (a LAN): it halves back towards `window`. A request sent again without its range
// filled halves the window too.
class PlaybackScheduler {
 public:
  // window >= 1 (the Replica checks its config); max_window at or below window: a fixed window.
  PlaybackScheduler(int64_t window, int64_t max_window, int64_t retry_ms);

  struct Request {
    NodeAddress author;
    NodeAddress target;
    int64_t start = 0;
    int64_t end = 0;
  };

  // The request to send now for this author's log, if any.
  std::optional<Request> Poll(NodeAddress author, const ChangeLog& log,
                              const std::vector<NodeAddress>& candidates, int64_t now_ms);
  // The same, calling `candidates` only when a request may be sent: they cost a scan of the
  // peers, and a replica polls every author on every tick while most polls send nothing.
  std::optional<Request> Poll(NodeAddress author, const ChangeLog& log,
                              const std::function<std::vector<NodeAddress>()>& candidates,
                              int64_t now_ms);
  // A change of the author's arrived: the first inside the outstanding range dates its answer.
  void OnArrival(NodeAddress author, int64_t seq, int64_t now_ms);
  // A response marker for the author's range arrived; `range_held`: every change of it is held
  // now. The next Poll may ask again at once, and a filled range sets the window.
  void OnResponse(NodeAddress author, int64_t start, int64_t end, bool range_held, int64_t now_ms);
  // The replica's tick: its spacing is the resolution of every time the scheduler is given.
  void OnTick(int64_t now_ms);
  // Forget everything outstanding (a restart of the protocol); the windows learned stay.
  void Clear() { outstanding_.clear(); }
  bool idle() const { return outstanding_.empty(); }
  // Consecutive requests for the author's first gap that brought nothing.
  uint64_t attempts(NodeAddress author) const {
    auto it = outstanding_.find(author);
    return it == outstanding_.end() ? 0 : it->second.attempts;
  }
  // The most changes the next request for this author's log covers.
  int64_t window(NodeAddress author) const {
    auto it = windows_.find(author);
    return it == windows_.end() ? window_ : it->second;
  }
  uint64_t requests_sent() const { return requests_sent_; }

 private:
  struct Outstanding {
    int64_t start = 0;
    int64_t end = 0;
    int64_t sent_ms = 0;
    int64_t first_arrival_ms = -1;  // -1: nothing of the range arrived yet
    int64_t contiguous_at_send = 0;
    uint64_t attempts = 0;  // consecutive requests without progress
    bool answered = false;
    bool full = false;  // covered a whole window (a gap's tail may be shorter)
  };

  void Adapt(NodeAddress author, const Outstanding& o, int64_t now_ms);
  void Shrink(NodeAddress author);

  int64_t window_;
  int64_t max_window_;
  int64_t retry_ms_;
  int64_t last_tick_ms_ = -1;
  int64_t tick_ms_ = 0;  // the spacing of the last two ticks
  std::map<NodeAddress, Outstanding> outstanding_;
  std::map<NodeAddress, int64_t> windows_;  // authors whose window left `window_`
  uint64_t requests_sent_ = 0;
};

}  // namespace dt
