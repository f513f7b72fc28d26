#include "pdu/pdu_auth.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "pdu/pdu_traits.h"

namespace dt {
namespace {

Rejection Reject(RejectReason reason, std::string detail) { return {reason, std::move(detail)}; }

std::string_view VerdictText(ReplayWindow::Verdict v) {
  switch (v) {
    case ReplayWindow::Verdict::kOlderIncarnation:
      return "an older incarnation than one already heard";
    case ReplayWindow::Verdict::kSeen:
      return "a sequence already accepted";
    case ReplayWindow::Verdict::kBehindWindow:
      return "a sequence too far behind the newest to tell";
    case ReplayWindow::Verdict::kNew:
      break;
  }
  return "new";
}

}  // namespace

int64_t WallClockMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

PduAuthenticator::PduAuthenticator(NodeAddress local, PduAuthConfig config)
    : local_(local),
      config_(std::move(config)),
      clock_watch_(config_.clock_tolerance, config_.sender_names) {
  if (!config_.key) throw std::invalid_argument("PduAuthenticator: no exercise key");
  if (config_.clock_tolerance.count() <= 0) {
    throw std::invalid_argument(fmt::format("PduAuthenticator: clock tolerance {} ms must be > 0",
                                            config_.clock_tolerance.count()));
  }
  if (!config_.wall_clock_ms) throw std::invalid_argument("PduAuthenticator: clock is empty");
  incarnation_ = config_.incarnation != 0 ? config_.incarnation
                                          : static_cast<uint64_t>(config_.wall_clock_ms());
}

void PduAuthenticator::Sign(std::vector<uint8_t>& bytes) {
  AuthTrailer t;
  t.sender = local_;
  t.incarnation = incarnation_;
  t.sequence = ++sequence_;
  t.send_time_ms = static_cast<uint64_t>(config_.wall_clock_ms());
  // The trailer is written in place after the PDU and the MAC taken over the contiguous bytes,
  // without a separate buffer for the signed part.
  const size_t lcm_bytes = bytes.size();
  bytes.resize(lcm_bytes + kAuthTrailerBytes);
  const std::span<uint8_t> all(bytes);
  EncodeSignedPart(t, all.subspan(lcm_bytes).first<kAuthSignedBytes>());
  const Mac mac = config_.key->Compute(all.first(lcm_bytes + kAuthSignedBytes));
  std::copy(mac.begin(), mac.end(), all.last<kMacBytes>().begin());
}

std::optional<Rejection> PduAuthenticator::Verify(std::span<const uint8_t> bytes,
                                                  std::span<const uint8_t>& pdu) {
  if (bytes.size() > kMaxPduBytes) {
    return Reject(RejectReason::kOversized,
                  fmt::format("{} bytes > {}", bytes.size(), kMaxPduBytes));
  }
  const std::optional<AuthTrailer> t = ParseTrailer(bytes);
  if (!t) {
    // A trailer of another version (a process of another release) is named as such: its MAC
    // is not this version's, so it authenticates nothing here.
    if (bytes.size() >= kAuthTrailerBytes) {
      const auto magic = bytes.subspan(bytes.size() - kAuthTrailerBytes, kAuthMagic.size());
      if (std::equal(kAuthMagic.begin(), kAuthMagic.end() - 1, magic.begin()) &&
          magic.back() != kAuthMagic.back()) {
        return Reject(RejectReason::kUnauthenticated,
                      fmt::format("{} bytes with a trailer of version '{}', this process reads "
                                  "version '{}' only",
                                  bytes.size(), static_cast<char>(magic.back()),
                                  static_cast<char>(kAuthMagic.back())));
      }
    }
    return Reject(RejectReason::kUnauthenticated,
                  fmt::format("{} bytes without an authentication trailer", bytes.size()));
  }
  const auto lcm = bytes.first(bytes.size() - kAuthTrailerBytes);
  if (!config_.key->Verify(bytes.first(lcm.size() + kAuthSignedBytes), t->mac)) {
    return Reject(RejectReason::kBadMac,
                  fmt::format("the MAC of a PDU claiming to be from {} does not match the "
                              "exercise key",
                              t->sender.ToString()));
  }
  const std::optional<NodeAddress> field = PeekSender(lcm);
  if (!field || *field != t->sender) {
    return Reject(RejectReason::kSenderMismatch,
                  fmt::format("trailer sender {} but PDU sender {}", t->sender.ToString(),
                              field ? field->ToString() : std::string("(none)")));
  }
  const int64_t now_ms = config_.wall_clock_ms();
  const int64_t tolerance_ms = config_.clock_tolerance.count();
  if (t->send_time_ms > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()) ||
      std::abs(now_ms - static_cast<int64_t>(t->send_time_ms)) > tolerance_ms) {
    if (t->send_time_ms <= static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      clock_watch_.Stale(t->sender, static_cast<int64_t>(t->send_time_ms) - now_ms, now_ms,
                         AgreeingSenders(now_ms, t->sender));
    }
    const double age_s =
        static_cast<double>(now_ms) / 1000.0 - static_cast<double>(t->send_time_ms) / 1000.0;
    return Reject(
        RejectReason::kStale,
        fmt::format("sent by {} {:.3f} s {} this host's clock (tolerance {:.3f} s)",
                    t->sender.ToString(), std::abs(age_s), age_s >= 0 ? "before" : "after",
                    static_cast<double>(tolerance_ms) / 1000.0));
  }
  auto it = senders_.find(t->sender);
  if (it != senders_.end() && now_ms - it->second.last_accepted_ms > 2 * tolerance_ms) {
    senders_.erase(it);  // everything it sent before now is stale
    it = senders_.end();
  }
  if (it == senders_.end()) it = senders_.emplace(t->sender, Sender{}).first;
  const ReplayWindow::Verdict v = it->second.window.Accept(t->incarnation, t->sequence);
  if (v != ReplayWindow::Verdict::kNew) {
    return Reject(RejectReason::kReplayed,
                  fmt::format("{} incarnation {} sequence {}: {} (incarnation {}, highest {})",
                              t->sender.ToString(), t->incarnation, t->sequence, VerdictText(v),
                              it->second.window.incarnation(), it->second.window.highest()));
  }
  it->second.last_accepted_ms = now_ms;
  if (clock_watch_.watching()) clock_watch_.Accepted(t->sender, now_ms);
  pdu = lcm;
  return std::nullopt;
}

size_t PduAuthenticator::AgreeingSenders(int64_t now_ms, std::optional<NodeAddress> except) const {
  size_t n = 0;
  for (const auto& [sender, s] : senders_) {
    if (sender != except && now_ms - s.last_accepted_ms <= kClockWatchWindow.count()) ++n;
  }
  return n;
}

ClockReport PduAuthenticator::clock_report() const {
  const int64_t now_ms = config_.wall_clock_ms();
  return clock_watch_.Report(now_ms, AgreeingSenders(now_ms, std::nullopt));
}

}  // namespace dt
