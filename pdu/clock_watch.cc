#include "pdu/clock_watch.h"

#include <algorithm>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

#include "log/log.h"

namespace dt {
namespace {

// Offsets are clamped to this (about 31,000 years) so sums and spreads cannot overflow; a send
// time anywhere near it is no clock's, but it is still reported as far off.
constexpr int64_t kMaxOffsetMs = int64_t{1} << 50;
// Senders in the table at most: only key holders get this far (the MAC is checked first), so
// this bounds a broken or hostile key holder, never an exercise.
constexpr size_t kMaxSuspects = 1024;

// Whether a line last written at `last` may be written again at now_ms. A wall clock that went
// back (the fix for the very skew being reported) allows it too rather than silencing it.
bool Due(const std::optional<int64_t>& last, int64_t now_ms) {
  return !last || now_ms - *last >= kClockLogInterval.count() || now_ms < *last;
}

bool Recent(int64_t at_ms, int64_t now_ms) { return now_ms - at_ms <= kClockWatchWindow.count(); }

std::string_view Direction(int64_t offset_ms) { return offset_ms >= 0 ? "ahead of" : "behind"; }

double Seconds(int64_t ms) { return static_cast<double>(ms) / 1000.0; }

}  // namespace

int64_t ClockReport::worst_offset_ms() const {
  int64_t worst = 0;
  for (const ClockSuspect& s : suspects) {
    if (std::llabs(s.offset_ms) > std::llabs(worst)) worst = s.offset_ms;
  }
  return worst;
}

ClockWatch::ClockWatch(std::chrono::milliseconds tolerance,
                       std::map<NodeAddress, std::string> names)
    : tolerance_ms_(tolerance.count()), names_(std::move(names)) {}

std::string ClockWatch::Describe(NodeAddress a) const {
  const auto it = names_.find(a);
  return it == names_.end() ? a.ToString() : fmt::format("{} ({})", a.ToString(), it->second);
}

void ClockWatch::Sweep(int64_t now_ms) {
  std::erase_if(suspects_, [&](const auto& e) { return !Recent(e.second.last_stale_ms, now_ms); });
}

std::optional<int64_t> ClockWatch::OwnOffset(int64_t now_ms, size_t agreeing) const {
  if (agreeing > 0) return std::nullopt;
  size_t n = 0;
  int64_t lo = std::numeric_limits<int64_t>::max();
  int64_t hi = std::numeric_limits<int64_t>::min();
  int64_t sum = 0;  // at most kMaxSuspects offsets of at most 2^50: no overflow
  for (const auto& [sender, s] : suspects_) {
    if (!s.active || !Recent(s.last_stale_ms, now_ms)) continue;
    ++n;
    lo = std::min(lo, s.offset_ms);
    hi = std::max(hi, s.offset_ms);
    sum += s.offset_ms;
  }
  // The others must agree among themselves as the exercise requires (within the tolerance, which
  // also puts them all on one side of this host): then this host is the odd one out.
  if (n < kOwnClockMinSenders || hi - lo > tolerance_ms_ || (lo < 0 && hi > 0)) {
    return std::nullopt;
  }
  return -(sum / static_cast<int64_t>(n));
}

void ClockWatch::Stale(NodeAddress sender, int64_t offset_ms, int64_t now_ms,
                       size_t others_agreeing) noexcept {
  Sweep(now_ms);
  auto it = suspects_.find(sender);
  if (it == suspects_.end()) {
    if (suspects_.size() >= kMaxSuspects) return;
    it = suspects_.emplace(sender, Suspect{}).first;
  }
  Suspect& s = it->second;
  if (!s.active) {
    s.active = true;
    s.stale = 0;
    s.warned = false;
  }
  s.offset_ms = std::clamp(offset_ms, -kMaxOffsetMs, kMaxOffsetMs);
  ++s.stale;
  s.last_stale_ms = now_ms;
  // When this host's clock is the likely culprit, one line says so and names every sender,
  // instead of a line per sender that each blames the other host.
  if (const std::optional<int64_t> own = OwnOffset(now_ms, others_agreeing)) {
    if (Due(own_logged_ms_, now_ms)) LogOwn(*own, now_ms);
    return;
  }
  if (!Due(s.last_logged_ms, now_ms)) return;
  DT_LOG_WARN(
      "{}: PDUs from {} are stamped {:.1f} s {} this host's clock, beyond the exercise's {:g} s "
      "tolerance: they are dropped until the clocks agree (check NTP on both hosts); {} dropped "
      "so far",
      log::kClockSkewMarker, Describe(sender), Seconds(std::llabs(s.offset_ms)),
      Direction(s.offset_ms), Seconds(tolerance_ms_), s.stale);
  s.last_logged_ms = now_ms;
  s.warned = true;
  ++lines_logged_;
}

void ClockWatch::LogOwn(int64_t own_offset_ms, int64_t now_ms) {
  std::string senders;
  for (const auto& [sender, s] : suspects_) {
    if (!s.active || !Recent(s.last_stale_ms, now_ms)) continue;
    if (!senders.empty()) senders += ", ";
    senders += Describe(sender);
  }
  DT_LOG_WARN(
      "{}: every PDU received is stamped about {:.0f} s {} this host's clock: this host's clock "
      "is probably {:.0f} s {} the exercise (check NTP on this host); PDUs from {} are dropped "
      "until it agrees",
      log::kClockSkewMarker, Seconds(std::llabs(own_offset_ms)), Direction(-own_offset_ms),
      Seconds(std::llabs(own_offset_ms)), Direction(own_offset_ms), senders);
  own_logged_ms_ = now_ms;
  own_warned_ = true;
  ++lines_logged_;
}

void ClockWatch::Accepted(NodeAddress sender, int64_t now_ms) noexcept {
  if (own_warned_) {
    own_warned_ = false;
    DT_LOG_INFO("{} over: a PDU from {} is accepted, so this host's clock agrees with it again",
                log::kClockSkewMarker, Describe(sender));
  }
  const auto it = suspects_.find(sender);
  if (it != suspects_.end() && it->second.active) {
    Suspect& s = it->second;
    s.active = false;
    if (s.warned) {
      s.warned = false;
      DT_LOG_INFO(
          "{} over: PDUs from {} are accepted again, its clock and this host's agree within the "
          "exercise's {:g} s tolerance ({} were dropped as stale)",
          log::kClockSkewMarker, Describe(sender), Seconds(tolerance_ms_), s.stale);
    }
  }
  Sweep(now_ms);
}

ClockReport ClockWatch::Report(int64_t now_ms, size_t agreeing) const {
  ClockReport r;
  for (const auto& [sender, s] : suspects_) {
    if (s.active && Recent(s.last_stale_ms, now_ms)) {
      r.suspects.push_back({sender, s.offset_ms, s.stale});
    }
  }
  r.own_offset_ms = OwnOffset(now_ms, agreeing);
  return r;
}

}  // namespace dt
