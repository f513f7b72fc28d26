// MaxFeature reports and sign-on: what a replica tells of the logs it holds, and how a node learns
// its own last numbers (docs/protocol.md, "Recovering what was missed", "Sign-on").
#include <algorithm>

#include <fmt/format.h>

#include "engine/replica.h"
#include "log/log.h"

namespace dt {

void Replica::OnMaxFeature(const dtpdu::max_feature_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  // A MaxFeature names the sender's ground as it is now: one naming ours is judged by
  // AdmitsGround below, not refused for what an earlier report said (a member restarted on the
  // exercise's ground is believed again).
  if (pdu.ground_digest[0] == static_cast<int64_t>(ground_digest_.high) &&
      pdu.ground_digest[1] == static_cast<int64_t>(ground_digest_.low)) {
    peer_grounds_.erase(sender);
  }
  if (!AdmitsSender(sender)) return;
  const auto role = static_cast<NodeRole>(pdu.role);
  if (!AdmitsRole(sender, role, "a MaxFeature")) return;
  if (role == NodeRole::kObserver) {
    // An observer reports nothing and signs on to no one: it is not counted (docs/view.md).
    Refused(counters_.refused_role,
            fmt::format("a MaxFeature from {}, an observer", sender.ToString()));
    return;
  }
  if (!AdmitsGround(sender, role, pdu)) return;
  if (!AdmitsClock(sender, static_cast<uint64_t>(pdu.lamport))) return;
  HeardFrom(sender, role);
  ObserveLamport(static_cast<uint64_t>(pdu.lamport));
  const NodeAddress subject = FromPdu(pdu.subject);
  if (pdu.sign_on && sender != config_.address) {
    sign_on_requests_.insert(sender);
  }
  if (!IsMember(subject)) {
    Refused(counters_.refused_claim, fmt::format("a claim by {} about {}, which is not a member",
                                                 sender.ToString(), subject.ToString()));
    return;
  }
  if (RoleOf(subject, NodeRole::kNode) == NodeRole::kObserver) {
    Refused(counters_.refused_claim, fmt::format("a claim by {} about {}, an observer",
                                                 sender.ToString(), subject.ToString()));
    return;
  }
  if (subject == config_.address) {
    ClaimAboutSelf(sender, role, pdu);
    return;
  }
  if (subject != sender && !IsServerRole(role)) {
    // A node speaks about another node only to answer that node's sign-on: the newcomer's
    // business, not evidence for anyone else.
    return;
  }
  LogOf(subject).Report(sender, pdu.max_change_seq);
  auto& max = max_feature_[subject];
  max = std::max(max, pdu.max_feature_number);
  if (signing_on_ && IsServerRole(role) && subject != sender) {
    // A node the server knows: it too may hold a change of this node the server never got.
    sign_on_expected_.insert(subject);
  }
}

void Replica::ClaimAboutSelf(NodeAddress sender, NodeRole role, const dtpdu::max_feature_t& pdu) {
  if (signing_on_ && !pdu.sign_on) sign_on_answered_by_.insert(sender);
  if (!IsServerRole(role)) {
    // A peer's answer to this node's sign-on: the highest change of this node it holds. Applied,
    // bounded, when the sign-on completes; once signed on, this node knows its own counters.
    if (signing_on_) {
      auto& claim = sign_on_peer_claims_[sender];
      claim.change_seq = std::max(claim.change_seq, pdu.max_change_seq);
      claim.feature_number = std::max(claim.feature_number, pdu.max_feature_number);
    }
    return;
  }
  // A server reports only what it has made durable. While signing on it is the authority on this
  // node's counters; afterwards this node issued everything itself, and a previous incarnation
  // can have left at most a window of changes the server had not acknowledged.
  int64_t seq = pdu.max_change_seq;
  int64_t number = pdu.max_feature_number;
  if (signed_on_) {
    const int64_t seq_bound = own_change_seq_ + config_.playback_window;
    const int64_t number_bound = own_feature_number_ + config_.playback_window;
    if (seq > seq_bound || number > number_bound) {
      Refused(counters_.refused_claim,
              fmt::format("{}'s claim that this node made {} changes and {} features (it made "
                          "{} and {})",
                          sender.ToString(), seq, number, own_change_seq_, own_feature_number_));
      return;
    }
  }
  LogOf(config_.address).Report(sender, seq);
  auto& max = max_feature_[config_.address];
  max = std::max(max, number);
  // Never reuse a number anyone has seen, even after losing all local state.
  own_feature_number_ = std::max(own_feature_number_, number);
  own_change_seq_ = std::max(own_change_seq_, seq);
  acknowledged_change_seq_ = std::max(acknowledged_change_seq_, seq);
  // Known to exist even if the server falls silent before this node has fetched them.
  LogOf(config_.address).RaiseFloor(own_change_seq_);
  if (signing_on_) server_answered_ = true;
}

void Replica::SignOn(int64_t now_ms) {
  now_ms_ = std::max(now_ms_, now_ms);
  scheduler_.Clear();
  if (observer()) {
    // Nothing to learn about itself (it issues nothing) and no one waits for it: it listens.
    signed_on_ = true;
    signing_on_ = false;
    return;
  }
  if (IsServerRole(config_.role)) {
    // A server is its own authority on its numbers (its store); it asks the nodes for theirs.
    signed_on_ = true;
    signing_on_ = false;
  } else {
    signed_on_ = false;
    signing_on_ = true;
    server_answered_ = false;
    sign_on_answered_by_.clear();
    sign_on_expected_.clear();
    sign_on_peer_claims_.clear();
  }
  sign_on_started_ms_ = now_ms_;
  sign_on_sent_ms_ = now_ms_;
  SendReport(config_.address, /*sign_on=*/true);
}

bool Replica::AnswersForServer() const {
  if (config_.role == NodeRole::kServer) return true;
  if (config_.role != NodeRole::kStandby) return false;
  for (const auto& [addr, p] : peers_) {
    if (p.role == NodeRole::kServer && !IsSilent(addr)) return false;
  }
  return true;
}

void Replica::SendReport(NodeAddress subject, bool sign_on, bool answer) {
  dtpdu::max_feature_t pdu{};
  pdu.subject = ToPdu(subject);
  auto mf = max_feature_.find(subject);
  pdu.max_feature_number = mf == max_feature_.end() ? 0 : mf->second;
  auto lg = logs_.find(subject);
  if (subject == config_.address) {
    pdu.max_feature_number = std::max(pdu.max_feature_number, own_feature_number_);
  }
  if (IsServerRole(config_.role)) {
    // A server vouches only for what it has stored: the durable gap-free point.
    auto d = durable_.find(subject);
    pdu.max_change_seq = d == durable_.end() ? 0 : d->second;
    if (subject == config_.address) pdu.max_change_seq = own_change_seq_;
  } else if (subject == config_.address) {
    pdu.max_change_seq = own_change_seq_;
  } else if (answer) {
    // Everything held: this node may hold a later change of the subject than the server got.
    pdu.max_change_seq = lg == logs_.end() ? 0 : lg->second.max_held();
  } else {
    pdu.max_change_seq = lg == logs_.end() ? 0 : lg->second.contiguous();
  }
  pdu.lamport = static_cast<int64_t>(lamport_);
  pdu.role = static_cast<uint8_t>(config_.role);
  pdu.sign_on = sign_on;
  pdu.ground_digest[0] = static_cast<int64_t>(ground_digest_.high);
  pdu.ground_digest[1] = static_cast<int64_t>(ground_digest_.low);
  if (auto s = bus_.Publish(pdu); !s) {
    DT_LOG_WARN("replica {}: MaxFeature failed: {}", config_.address.ToString(), s.error().message);
  }
}

void Replica::SendReports() {
  SendReport(config_.address, false);
  if (!AnswersForServer()) return;
  for (const auto& [author, log] : logs_) {
    if (author != config_.address && log.max_held() > 0) SendReport(author, false);
  }
}

void Replica::CompleteSignOn() {
  signed_on_ = true;
  signing_on_ = false;
  // Peers may hold changes of the previous incarnation the server never got. That incarnation
  // left at most a window of changes unacknowledged, so a claim beyond that is not believed.
  for (const auto& [peer, claim] : sign_on_peer_claims_) {
    int64_t seq = claim.change_seq;
    int64_t number = claim.feature_number;
    if (config_.require_server) {
      const int64_t seq_bound = acknowledged_change_seq_ + config_.playback_window;
      const int64_t number_bound = own_feature_number_ + config_.playback_window;
      if (seq > seq_bound || number > number_bound) {
        Refused(counters_.refused_claim,
                fmt::format("{}'s answer that this node made {} changes and {} features; at "
                            "most {} and {} can be unacknowledged",
                            peer.ToString(), seq, number, seq_bound, number_bound));
        seq = std::min(seq, seq_bound);
        number = std::min(number, number_bound);
      }
    }
    LogOf(config_.address).Report(peer, seq);
    own_change_seq_ = std::max(own_change_seq_, seq);
    LogOf(config_.address).RaiseFloor(own_change_seq_);
    own_feature_number_ = std::max(own_feature_number_, number);
  }
  sign_on_peer_claims_.clear();
  if (!had_reservation_) {
    // Without a reservation, the previous incarnation may have created up to a window of
    // features nobody acknowledged; skipping a window of numbers covers those the rest of the
    // exercise still holds (docs/protocol.md, "No ID issued twice").
    own_feature_number_ =
        std::min<int64_t>(kMaxSerial, own_feature_number_ + config_.playback_window);
  }
}

}  // namespace dt
