#include "engine/playback_scheduler.h"

#include <algorithm>
#include <cmath>

namespace dt {

PlaybackScheduler::PlaybackScheduler(int64_t window, int64_t max_window, int64_t retry_ms)
    : window_(window), max_window_(std::max(window, max_window)), retry_ms_(retry_ms) {}

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
  bool unfilled = false;  // the last request's range is asked for again, not all of it held
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
    unfilled = log.contiguous() < o.end;
  }
  const std::vector<NodeAddress> candidates = list_candidates();
  if (candidates.empty()) return std::nullopt;
  if (unfilled) Shrink(author);
  const int64_t w = window(author);
  auto [start, end] = log.FirstGap();
  Outstanding o;
  o.full = end - start + 1 >= w;
  end = std::min(end, start + w - 1);
  o.start = start;
  o.end = end;
  o.sent_ms = now_ms;
  o.contiguous_at_send = log.contiguous();
  o.attempts = attempts;
  outstanding_[author] = o;
  ++requests_sent_;
  return Request{author, candidates[attempts % candidates.size()], start, end};
}

void PlaybackScheduler::OnArrival(NodeAddress author, int64_t seq, int64_t now_ms) {
  auto it = outstanding_.find(author);
  if (it == outstanding_.end()) return;
  Outstanding& o = it->second;
  if (o.first_arrival_ms < 0 && seq >= o.start && seq <= o.end) o.first_arrival_ms = now_ms;
}

void PlaybackScheduler::OnResponse(NodeAddress author, int64_t start, int64_t end, bool range_held,
                                   int64_t now_ms) {
  auto it = outstanding_.find(author);
  if (it == outstanding_.end()) return;
  Outstanding& o = it->second;
  if (o.start != start || o.end != end || o.answered) return;
  o.answered = true;
  if (range_held) Adapt(author, o, now_ms);
}

void PlaybackScheduler::OnTick(int64_t now_ms) {
  if (last_tick_ms_ >= 0 && now_ms > last_tick_ms_) tick_ms_ = now_ms - last_tick_ms_;
  last_tick_ms_ = std::max(last_tick_ms_, now_ms);
}

void PlaybackScheduler::Adapt(NodeAddress author, const Outstanding& o, int64_t now_ms) {
  // Nothing of the range arrived after the request (another's answer filled it): no measure.
  if (max_window_ == window_ || o.first_arrival_ms < 0) return;
  const int64_t w = window(author);
  // The wait for the first change, less what the replica's own clock cannot resolve: a LAN's
  // round trip hides inside one tick, and only a longer wait is worth a larger window.
  const int64_t latency_ms = o.first_arrival_ms - o.sent_ms - tick_ms_;
  int64_t next = w / 2;
  if (latency_ms > 0) {
    // A range that arrived within one tick came at least this fast; the bound on growth below
    // keeps such an estimate from running away.
    const double transfer_ms =
        static_cast<double>(std::max<int64_t>({now_ms - o.first_arrival_ms, tick_ms_, int64_t{1}}));
    const double per_ms = static_cast<double>(o.end - o.start + 1) / transfer_ms;
    // Four latencies' worth: the wait is then at most a fifth of each window's time. Half the
    // retry time's worth at most: a window must arrive before it is asked for again.
    const double target = std::min(4.0 * static_cast<double>(latency_ms) * per_ms,
                                   per_ms * static_cast<double>(retry_ms_) / 2.0);
    const int64_t most = o.full ? 2 * w : w;  // only a full window shows that more would help
    next = std::clamp(static_cast<int64_t>(std::llround(target)), w / 2, most);
  }
  const int64_t bounded = std::clamp(next, window_, max_window_);
  if (bounded == window_) {
    windows_.erase(author);
  } else {
    windows_[author] = bounded;
  }
}

void PlaybackScheduler::Shrink(NodeAddress author) {
  auto it = windows_.find(author);
  if (it == windows_.end()) return;
  it->second /= 2;
  if (it->second <= window_) windows_.erase(it);
}

}  // namespace dt
