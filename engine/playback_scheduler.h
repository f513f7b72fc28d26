// PlaybackScheduler: which missing ranges to request, from whom and when, per author.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "base/feature_id.h"
#include "engine/change_log.h"

namespace dt {

// One request outstanding per author, covering at most `window` sequences. A request that gets
// no progress within retry_ms, or whose answer leaves the gap open, is sent again to the next
// candidate (candidates are ordered by the caller: the author first, then the servers, then any
// other live replica).
class PlaybackScheduler {
 public:
  PlaybackScheduler(int64_t window, int64_t retry_ms) : window_(window), retry_ms_(retry_ms) {}

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
  // A response marker for the author's range arrived: the next Poll may ask again at once.
  void OnResponse(NodeAddress author, int64_t start, int64_t end);
  // Forget everything outstanding (a restart of the protocol).
  void Clear() { outstanding_.clear(); }
  bool idle() const { return outstanding_.empty(); }
  // Consecutive requests for the author's first gap that brought nothing.
  uint64_t attempts(NodeAddress author) const {
    auto it = outstanding_.find(author);
    return it == outstanding_.end() ? 0 : it->second.attempts;
  }
  uint64_t requests_sent() const { return requests_sent_; }

 private:
  struct Outstanding {
    int64_t start = 0;
    int64_t end = 0;
    int64_t sent_ms = 0;
    int64_t contiguous_at_send = 0;
    uint64_t attempts = 0;  // consecutive requests without progress
    bool answered = false;
  };

  int64_t window_;
  int64_t retry_ms_;
  std::map<NodeAddress, Outstanding> outstanding_;
  uint64_t requests_sent_ = 0;
};

}  // namespace dt
