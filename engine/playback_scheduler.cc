#include "engine/playback_scheduler.h"

#include <algorithm>

namespace dt {

std::optional<PlaybackScheduler::Request> PlaybackScheduler::Poll(
    NodeAddress author, const ChangeLog& log, const std::vector<NodeAddress>& candidates,
    int64_t now_ms) {
  return Poll(
      author, log, [&] { return candidates; }, now_ms);
}

std::optional<PlaybackScheduler::Request> PlaybackScheduler::Poll(
    NodeAddress author, const ChangeLog& log,
    const std::function<std::vector<NodeAddress>()>& list_candidates, int64_t now_ms) {
  auto it = outstanding_.find(author);
  if (!log.has_gap()) {
    if (it != outstanding_.end()) outstanding_.erase(it);
    return std::nullopt;
  }
  // Every return before the candidates are needed changes nothing, so asking for them only then
  // gives the same requests as asking first.
  uint64_t attempts = 0;
  if (it != outstanding_.end()) {
    Outstanding& o = it->second;
    const bool progressed = log.contiguous() > o.contiguous_at_send;
    if (log.contiguous() < o.end && !o.answered && !progressed && now_ms - o.sent_ms < retry_ms_) {
      return std::nullopt;  // still waiting for this request
    }
    if (log.contiguous() < o.end && !o.answered && progressed && now_ms - o.sent_ms < retry_ms_) {
      return std::nullopt;  // answers are arriving
    }
    attempts = progressed ? 0 : o.attempts + 1;
  }
  const std::vector<NodeAddress> candidates = list_candidates();
  if (candidates.empty()) return std::nullopt;
  auto [start, end] = log.FirstGap();
  end = std::min(end, start + window_ - 1);
  Outstanding o;
  o.start = start;
  o.end = end;
  o.sent_ms = now_ms;
  o.contiguous_at_send = log.contiguous();
  o.attempts = attempts;
  outstanding_[author] = o;
  ++requests_sent_;
  return Request{author, candidates[attempts % candidates.size()], start, end};
}

void PlaybackScheduler::OnResponse(NodeAddress author, int64_t start, int64_t end) {
  auto it = outstanding_.find(author);
  if (it == outstanding_.end()) return;
  if (it->second.start == start && it->second.end == end) it->second.answered = true;
}

}  // namespace dt
