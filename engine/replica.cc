#include "engine/replica.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

void CheckConfig(const ReplicaConfig& c) {
  if (c.max_feature_period_ms <= 0 || c.silence_ms <= 0 || c.playback_retry_ms <= 0) {
    throw std::invalid_argument(fmt::format(
        "replica {}: max_feature_period_ms {}, silence_ms {} and playback_retry_ms {} must be > 0",
        c.address.ToString(), c.max_feature_period_ms, c.silence_ms, c.playback_retry_ms));
  }
  if (c.anti_entropy_period_ms < 0) {
    throw std::invalid_argument(fmt::format("replica {}: anti_entropy_period_ms {} must be >= 0",
                                            c.address.ToString(), c.anti_entropy_period_ms));
  }
  if (c.gap_give_up_ms != 0 && c.gap_give_up_ms <= 2 * c.silence_ms) {
    throw std::invalid_argument(
        fmt::format("replica {}: gap_give_up_ms {} must be 0 (never) or more than 2 x silence_ms "
                    "({}): a crashed node needs that long to come back and void its own gaps",
                    c.address.ToString(), c.gap_give_up_ms, c.silence_ms));
  }
  if (c.playback_window < 1 || c.playback_window > kMaxPlaybackSpan) {
    throw std::invalid_argument(fmt::format("replica {}: playback_window {} is outside [1, {}]",
                                            c.address.ToString(), c.playback_window,
                                            kMaxPlaybackSpan));
  }
  if ((c.role == NodeRole::kNode || c.role == NodeRole::kObserver) && c.store != nullptr) {
    throw std::invalid_argument(
        fmt::format("replica {}: a {} has no store (role server or standby)", c.address.ToString(),
                    NodeRoleName(c.role)));
  }
  if (!c.members.empty()) {
    auto me = c.members.find(c.address);
    if (me == c.members.end() || me->second != c.role) {
      throw std::invalid_argument(
          fmt::format("replica {}: not in the exercise's members with role {}",
                      c.address.ToString(), NodeRoleName(c.role)));
    }
  }
}

}  // namespace

Replica::Replica(ReplicaConfig config, HeightGrid ground, PduBus& bus)
    : config_(config),
      bus_(bus),
      records_(std::move(ground)),
      scheduler_(config.playback_window, config.playback_retry_ms) {
  CheckConfig(config_);
  bus_.Subscribe<dtpdu::construct_t>([this](const dtpdu::construct_t& p) { OnConstruct(p); });
  bus_.Subscribe<dtpdu::update_t>([this](const dtpdu::update_t& p) { OnUpdate(p); });
  bus_.Subscribe<dtpdu::destruct_t>([this](const dtpdu::destruct_t& p) { OnDestruct(p); });
  bus_.Subscribe<dtpdu::earth_move_t>([this](const dtpdu::earth_move_t& p) { OnEarthMove(p); });
  bus_.Subscribe<dtpdu::max_feature_t>([this](const dtpdu::max_feature_t& p) { OnMaxFeature(p); });
  bus_.Subscribe<dtpdu::playback_t>([this](const dtpdu::playback_t& p) { OnPlayback(p); });
  if (config_.store != nullptr) {
    auto loaded = config_.store->LoadAll();
    if (!loaded) {
      load_status_ = loaded.error();
      DT_LOG_ERROR("replica {}: loading the store failed: {}", config_.address.ToString(),
                   loaded.error().message);
    } else {
      for (const Change& c : loaded.value()) Accept(c, /*from_store=*/true);
      pending_store_.clear();
      for (const auto& [author, log] : logs_) durable_[author] = log.contiguous();
      if (!loaded.value().empty()) {
        DT_LOG_INFO("replica {}: resumed {} stored changes, {} live features",
                    config_.address.ToString(), loaded.value().size(), records_.live_count());
      }
    }
  }
  if (config_.ids != nullptr && load_status_.ok()) {
    auto reserved = config_.ids->Load();
    if (!reserved) {
      load_status_ = reserved.error();
      DT_LOG_ERROR("replica {}: loading the feature number reservation failed: {}",
                   config_.address.ToString(), reserved.error().message);
    } else if (reserved.value()) {
      // Every number up to the reservation may have been issued by an earlier incarnation.
      had_reservation_ = true;
      reserved_feature_number_ = *reserved.value();
      own_feature_number_ = std::max(own_feature_number_, reserved_feature_number_);
    }
  }
  anti_entropy_ = std::make_unique<AntiEntropy>(
      AntiEntropyConfig{config_.address, config_.role, config_.anti_entropy_period_ms,
                        config_.playback_retry_ms, config_.silence_ms, config_.store},
      logs_, records_, bus_,
      [this](const Change& c, NodeAddress requester) {
        Publish(c, requester);
        ++counters_.played_back;
      },
      [this](const Change& /*old_copy*/, const Change& now_held) {
        // What Accept notes for a change it logs, for the copy that took the slot.
        ObserveLamport(now_held.stamp.lamport);
        NoteOwn(now_held);
        auto& max = max_feature_[OriginOf(now_held.id)];
        max = std::max<int64_t>(max, now_held.id.number);
      },
      AntiEntropy::Admission{[this](NodeAddress sender, NodeRole role) {
                               return AdmitsSender(sender) &&
                                      AdmitsRole(sender, role, "an AntiEntropy");
                             },
                             [this](NodeAddress sender, const Change& copy) {
                               return Admits(sender, copy.author(), copy.stamp.lamport);
                             }},
      [this](NodeAddress peer, NodeAddress author, int64_t max_held) {
        HeldBeyond(peer, author, max_held);
      });
}

Replica::~Replica() = default;

// ---- accepting changes ----

void Replica::ObserveLamport(uint64_t lamport) { lamport_ = std::max(lamport_, lamport); }

void Replica::NoteOwn(const Change& change) {
  if (change.author() == config_.address) {
    own_change_seq_ = std::max<int64_t>(own_change_seq_, change.stamp.change_seq);
    logs_[config_.address].RaiseFloor(own_change_seq_);
  }
  if (OriginOf(change.id) == config_.address) {
    own_feature_number_ = std::max<int64_t>(own_feature_number_, change.id.number);
  }
}

bool Replica::Accept(const Change& change, bool from_store) {
  ObserveLamport(change.stamp.lamport);
  if (!logs_[change.author()].Insert(change)) return false;
  NoteOwn(change);
  auto& max = max_feature_[OriginOf(change.id)];
  max = std::max<int64_t>(max, change.id.number);
  if (records_.Apply(change) == RecordStore::Outcome::kApplied) {
    ++counters_.applied;
  } else {
    ++counters_.ignored_stale;
  }
  if (config_.store != nullptr && !from_store) pending_store_.push_back(change);
  return true;
}

void Replica::Publish(const Change& change, std::optional<NodeAddress> playback_for) {
  Result<int64_t> sent = Error{""};
  switch (change.kind) {
    case ChangeKind::kConstruct: {
      if (change.params.type == FeatureType::kEarthMove) {
        auto pdu = ToEarthMove(ToFeaturePdu(change));
        if (playback_for) {
          pdu.is_playback = true;
          pdu.playback_for = ToPdu(*playback_for);
        }
        sent = bus_.Publish(pdu);
        break;
      }
      auto pdu = ToConstruct(ToFeaturePdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
    case ChangeKind::kUpdate: {
      auto pdu = ToUpdate(ToFeaturePdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
    case ChangeKind::kDestruct: {
      auto pdu = ToDestruct(ToDestructPdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
  }
  if (sent) {
    ++counters_.sent;
  } else {
    DT_LOG_WARN("replica {}: sending change {}:{} failed: {}", config_.address.ToString(),
                change.author().ToString(), change.stamp.change_seq, sent.error().message);
  }
}

void Replica::HeardFrom(NodeAddress sender, std::optional<NodeRole> role) {
  if (sender == config_.address) return;
  // An observer's playback requests are answered, but it is no peer: never a candidate, never
  // waited for in a sign-on, never a live holder when giving up (docs/protocol.md, "Observers").
  if (RoleOf(sender, NodeRole::kNode) == NodeRole::kObserver) return;
  Peer& p = peers_[sender];
  p.last_heard_ms = now_ms_;
  if (role) p.role = *role;
}

NodeRole Replica::RoleOf(NodeAddress a, NodeRole claimed) const {
  if (config_.members.empty()) return claimed;
  auto it = config_.members.find(a);
  return it == config_.members.end() ? claimed : it->second;
}

void Replica::Refused(uint64_t& counter, const std::string& what) {
  ++counter;
  ++refusals_since_log_;
  // One line a second at most: a hostile or broken peer must not flood the log.
  if (last_refusal_log_ms_ < 0 || now_ms_ - last_refusal_log_ms_ >= 1000) {
    DT_LOG_WARN("replica {}: refused {} ({} refused since the last such line)",
                config_.address.ToString(), what, refusals_since_log_);
    last_refusal_log_ms_ = now_ms_;
    refusals_since_log_ = 0;
  }
}

bool Replica::Admits(NodeAddress sender, NodeAddress author, uint64_t lamport) {
  if (!IsMember(author)) {
    Refused(
        counters_.refused_stranger,
        fmt::format("a change by {}, which is not a member of the exercise", author.ToString()));
    return false;
  }
  if (RoleOf(author, NodeRole::kNode) == NodeRole::kObserver) {
    Refused(counters_.refused_role,
            fmt::format("a change by {}, an observer, which creates nothing", author.ToString()));
    return false;
  }
  return AdmitsClock(sender, lamport);
}

bool Replica::AdmitsClock(NodeAddress sender, uint64_t lamport) {
  if (lamport >= kMaxLamport || lamport > lamport_ + kMaxLamportLead) {
    Refused(counters_.refused_lamport,
            fmt::format("a PDU from {} with Lamport clock {}, more than {} ahead of {}",
                        sender.ToString(), lamport, kMaxLamportLead, lamport_));
    return false;
  }
  return true;
}

bool Replica::AdmitsRole(NodeAddress sender, NodeRole role, std::string_view what) {
  if (RoleOf(sender, role) == role) return true;
  Refused(counters_.refused_role,
          fmt::format("{} from {} claiming role {}; the exercise file says {}", what,
                      sender.ToString(), NodeRoleName(role), NodeRoleName(RoleOf(sender, role))));
  return false;
}

bool Replica::AdmitsSender(NodeAddress sender) {
  if (IsMember(sender)) return true;
  Refused(counters_.refused_stranger,
          fmt::format("a PDU from {}, which is not a member of the exercise", sender.ToString()));
  return false;
}

void Replica::OnConstruct(const dtpdu::construct_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromConstruct(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(f.value(), ChangeKind::kConstruct);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnEarthMove(const dtpdu::earth_move_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromEarthMove(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  // An earth move is a Construct of its own feature: logged, played back and stored as one.
  const Change c = ChangeFrom(f.value(), ChangeKind::kConstruct);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnUpdate(const dtpdu::update_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromUpdate(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(f.value(), ChangeKind::kUpdate);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnDestruct(const dtpdu::destruct_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto d = FromDestruct(pdu);
  if (!d) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(d.value());
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnMaxFeature(const dtpdu::max_feature_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  const auto role = static_cast<NodeRole>(pdu.role);
  if (!AdmitsRole(sender, role, "a MaxFeature")) return;
  if (role == NodeRole::kObserver) {
    // An observer reports nothing and signs on to no one: it is not counted (docs/view.md).
    Refused(counters_.refused_role,
            fmt::format("a MaxFeature from {}, an observer", sender.ToString()));
    return;
  }
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
  logs_[subject].Report(sender, pdu.max_change_seq);
  auto& max = max_feature_[subject];
  max = std::max(max, pdu.max_feature_number);
  if (signing_on_ && IsServerRole(role) && subject != sender) {
    // A node the server knows: it too may hold a change of this node the server never got.
    sign_on_expected_.insert(subject);
  }
}

void Replica::HeldBeyond(NodeAddress peer, NodeAddress author, int64_t max_held) {
  // Own changes beyond own_change_seq are the sign-on's business (bounded there).
  if (author == config_.address || !IsMember(author)) return;
  ChangeLog& log = logs_[author];
  // Evidence to fetch, not a counter: bounded by a window beyond what is known, so a member that
  // lies moves no one far, and forgotten when the peer falls silent or the gap is given up on.
  const int64_t bound = log.max_known() + config_.playback_window;
  log.ReportHeld(peer, std::min(max_held, bound));
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
  logs_[config_.address].Report(sender, seq);
  auto& max = max_feature_[config_.address];
  max = std::max(max, number);
  // Never reuse a number anyone has seen, even after losing all local state.
  own_feature_number_ = std::max(own_feature_number_, number);
  own_change_seq_ = std::max(own_change_seq_, seq);
  acknowledged_change_seq_ = std::max(acknowledged_change_seq_, seq);
  // Known to exist even if the server falls silent before this node has fetched them.
  logs_[config_.address].RaiseFloor(own_change_seq_);
  if (signing_on_) server_answered_ = true;
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
    scheduler_.OnResponse(subject, pdu.start, pdu.end);
    // An answer that closed its whole range asks for the next window at once, not at the next
    // tick: a catch-up then moves one window per round trip (30 Hz ticks made 10^5 changes take
    // 13 s). Any other answer waits for the tick, so retries and the rounds before a void keep
    // their pace.
    auto it = logs_.find(subject);
    if (pdu.range_complete && it != logs_.end() && it->second.contiguous() >= pdu.end) {
      RequestFor(subject, it->second);
    }
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

// ---- periodic work ----

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

bool Replica::IsSilent(NodeAddress node) const {
  auto it = peers_.find(node);
  return it == peers_.end() || it->second.last_heard_ms < 0 ||
         now_ms_ - it->second.last_heard_ms > config_.silence_ms;
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

void Replica::Commit() {
  if (config_.store == nullptr || pending_store_.empty()) return;
  const bool was_ok = store_status_.ok();
  store_status_ = config_.store->Append(pending_store_);
  if (!store_status_) {
    // Logged when the store starts failing, not on every retry.
    if (was_ok) {
      DT_LOG_ERROR(
          "replica {}: storing {} changes failed; they are not reported durable and "
          "are retried every tick: {}",
          config_.address.ToString(), pending_store_.size(), store_status_.error().message);
    }
    return;
  }
  if (!was_ok) {
    DT_LOG_INFO("replica {}: the store accepts changes again ({} stored)",
                config_.address.ToString(), pending_store_.size());
  }
  pending_store_.clear();
  for (const auto& [author, log] : logs_) durable_[author] = log.contiguous();
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

Status Replica::Flush() {
  Commit();
  return store_status_;
}

void Replica::Tick(int64_t now_ms) {
  now_ms_ = std::max(now_ms_, now_ms);
  Commit();
  if (signing_on_) {
    const int64_t waited = now_ms_ - sign_on_started_ms_;
    // Listen for silence_ms, so every live peer has been heard (each reports every period),
    // and wait for the answers of all of them: a peer may hold a later change of this node
    // than the server does.
    // Every peer heard since the sign-on began must have answered too: a peer may hold a later
    // change of this node than the server does (docs/protocol.md, "Sign-on").
    bool peers_answered = true;
    for (const auto& [addr, p] : peers_) {
      if (p.last_heard_ms >= sign_on_started_ms_ && !IsSilent(addr) &&
          sign_on_answered_by_.count(addr) == 0) {
        peers_answered = false;
      }
    }
    // Nodes the server knows are waited for too, unless still unheard after three silences
    // (gone for good), so a peer whose reports happened to be lost is not skipped.
    for (NodeAddress n : sign_on_expected_) {
      if (sign_on_answered_by_.count(n) == 0 &&
          !(IsSilent(n) && waited >= 3 * int64_t{config_.silence_ms})) {
        peers_answered = false;
      }
    }
    if ((server_answered_ && peers_answered && waited >= config_.silence_ms) ||
        (!config_.require_server && waited >= config_.silence_ms)) {
      CompleteSignOn();
    } else if (now_ms_ - sign_on_sent_ms_ >= config_.playback_retry_ms) {
      sign_on_sent_ms_ = now_ms_;
      SendReport(config_.address, /*sign_on=*/true);
    }
  }
  if (observer()) sign_on_requests_.clear();  // no answers, no reports: it is not counted
  if (!sign_on_requests_.empty()) {
    // Answer after the commit above, so a server's answer is durable.
    for (NodeAddress who : sign_on_requests_) {
      SendReport(who, false, /*answer=*/true);
      // A server reports only its gap-free durable point; changes of the newcomer it holds
      // beyond a gap are sent along, so the newcomer never reuses their sequences.
      auto lg = logs_.find(who);
      if (IsServerRole(config_.role) && lg != logs_.end()) {
        for (const Change* c :
             lg->second.Range(lg->second.contiguous() + 1, lg->second.max_held())) {
          Publish(*c, who);
          ++counters_.played_back;
        }
      }
    }
    sign_on_requests_.clear();
    SendReports();
    last_report_ms_ = now_ms_;
  }
  if (!observer() &&
      (last_report_ms_ < 0 || now_ms_ - last_report_ms_ >= config_.max_feature_period_ms)) {
    SendReports();
    last_report_ms_ = now_ms_;
  }
  ForgetSilentReporters();
  RequestMissing();
  anti_entropy_->Tick(now_ms_);
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
    logs_[config_.address].Report(peer, seq);
    own_change_seq_ = std::max(own_change_seq_, seq);
    logs_[config_.address].RaiseFloor(own_change_seq_);
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

Status Replica::ReserveFeatureNumbers(int64_t number) {
  if (config_.ids == nullptr || number <= reserved_feature_number_) return Status::Ok();
  // A window at a time: one write per window of creates, not one per create.
  const int64_t up_to = std::min<int64_t>(kMaxSerial, number + config_.playback_window);
  if (Status s = config_.ids->Reserve(up_to); !s) {
    return Error{fmt::format("node {} cannot reserve feature numbers up to {}: {}",
                             config_.address.ToString(), up_to, s.error().message)};
  }
  reserved_feature_number_ = up_to;
  return Status::Ok();
}

// ---- queries ----

std::string Replica::Digest() const { return ComputeDigest(records_.terrain()).ToHex(); }

bool Replica::caught_up() const {
  if (anti_entropy_->diverged()) return false;
  for (const auto& [author, log] : logs_) {
    if (log.has_gap()) return false;
  }
  return true;
}

Replica::Counters Replica::counters() const {
  Counters c = counters_;
  c.rejected += bus_.rejects().total();
  return c;
}

std::map<NodeAddress, int64_t> Replica::max_feature_known() const {
  std::map<NodeAddress, int64_t> out;
  for (const auto& [origin, n] : max_feature_) {
    if (n > 0) out[origin] = n;
  }
  if (own_feature_number_ > 0) out[config_.address] = own_feature_number_;
  return out;
}

std::map<NodeAddress, int64_t> Replica::contiguous_change_seq() const {
  std::map<NodeAddress, int64_t> out;
  for (const auto& [author, log] : logs_) out[author] = log.contiguous();
  return out;
}

}  // namespace dt
