// Playback: asking for the changes a log is missing, from whom, and answering such requests
// (docs/protocol.md, "Recovering what was missed").
#include <algorithm>

#include "engine/replica.h"
#include "log/log.h"

namespace dt {

void Replica::HeldBeyond(NodeAddress peer, NodeAddress author, int64_t max_held) {
  // Own changes beyond own_change_seq are the sign-on's business (bounded there).
  if (author == config_.address || !IsMember(author)) return;
  ChangeLog& log = LogOf(author);
  // Evidence to fetch, not a counter: bounded by a window beyond what is known, so a member that
  // lies moves no one far, and forgotten when the peer falls silent or the gap is given up on.
  const int64_t bound = log.max_known() + config_.playback_window;
  log.ReportHeld(peer, std::min(max_held, bound));
}

void Replica::OnPlayback(const dtpdu::playback_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  HeardFrom(sender, std::nullopt);
  if (pdu.range_kind != static_cast<uint8_t>(PlaybackRange::kChangeSeqs)) {
    return;  // feature-number ranges (thesis style) are not used: change sequences cover them
  }
  if (!pdu.is_response) {
    if (FromPdu(pdu.transmitting) == config_.address && !observer()) AnswerPlayback(pdu);
    return;
  }
  if (FromPdu(pdu.requesting) == config_.address) {
    const NodeAddress subject = FromPdu(pdu.subject);
    auto it = logs_.find(subject);
    const bool held = it != logs_.end() && it->second.contiguous() >= pdu.end;
    scheduler_.OnResponse(subject, pdu.start, pdu.end, held, now_ms_);
    // An answer that closed its whole range asks for the next window at once, not at the next
    // tick: a catch-up then moves one window per round trip (30 Hz ticks made 10^5 changes take
    // 13 s). Any other answer waits for the tick, so retries and the rounds before a void keep
    // their pace.
    if (pdu.range_complete && held) RequestFor(subject, it->second);
  }
}

void Replica::AnswerPlayback(const dtpdu::playback_t& request) {
  const NodeAddress subject = FromPdu(request.subject);
  const NodeAddress requester = FromPdu(request.requesting);
  auto it = logs_.find(subject);
  bool complete = false;
  if (it != logs_.end()) {
    for (const Change* c : it->second.Range(request.start, request.end)) {
      Publish(*c, requester);
      ++counters_.played_back;
    }
    complete = it->second.contiguous() >= request.end;
  }
  dtpdu::playback_t answer{};
  answer.requesting = request.requesting;
  answer.transmitting = ToPdu(config_.address);
  answer.subject = request.subject;
  answer.range_kind = request.range_kind;
  answer.start = request.start;
  answer.end = request.end;
  answer.is_response = true;
  answer.range_complete = complete;
  if (auto s = bus_.Publish(answer); !s) {
    DT_LOG_WARN("replica {}: playback answer failed: {}", config_.address.ToString(),
                s.error().message);
  }
}

std::vector<NodeAddress> Replica::Candidates(NodeAddress author) const {
  std::vector<NodeAddress> out;
  auto add = [&](NodeAddress a) {
    if (a != config_.address && std::find(out.begin(), out.end(), a) == out.end()) {
      out.push_back(a);
    }
  };
  if (!IsSilent(author)) add(author);
  for (NodeRole role : {NodeRole::kServer, NodeRole::kStandby}) {
    for (const auto& [addr, p] : peers_) {
      if (p.role == role && !IsSilent(addr)) add(addr);
    }
  }
  for (const auto& [addr, p] : peers_) {
    if (!IsSilent(addr)) add(addr);
  }
  return out;
}

void Replica::ForgetSilentReporters() {
  for (auto& [author, log] : logs_) {
    std::vector<NodeAddress> gone;
    for (const auto* claims : {&log.reports(), &log.held_by()}) {
      for (const auto& [reporter, seq] : *claims) {
        if (IsSilent(reporter)) gone.push_back(reporter);
      }
    }
    for (NodeAddress g : gone) log.ForgetReporter(g);
  }
}

void Replica::RequestMissing() {
  VoidLostOwnChanges();
  GiveUpOnGoneAuthors();
  for (const auto& [author, log] : logs_) RequestFor(author, log);
}

void Replica::RequestFor(NodeAddress author, const ChangeLog& log) {
  auto req = scheduler_.Poll(
      author, log, [this, author] { return Candidates(author); }, now_ms_);
  if (!req) return;
  dtpdu::playback_t pdu{};
  pdu.requesting = ToPdu(config_.address);
  pdu.transmitting = ToPdu(req->target);
  pdu.subject = ToPdu(author);
  pdu.range_kind = static_cast<uint8_t>(PlaybackRange::kChangeSeqs);
  pdu.start = req->start;
  pdu.end = req->end;
  if (auto s = bus_.Publish(pdu); !s) {
    DT_LOG_WARN("replica {}: playback request failed: {}", config_.address.ToString(),
                s.error().message);
  }
}

}  // namespace dt
