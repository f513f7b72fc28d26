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
  if (c.playback_window_max < 1 || c.playback_window_max > kMaxPlaybackSpan) {
    throw std::invalid_argument(fmt::format("replica {}: playback_window_max {} is outside [1, {}]",
                                            c.address.ToString(), c.playback_window_max,
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
    : Replica(std::move(config), BaseGround{std::move(ground), {}}, bus) {}

Replica::Replica(ReplicaConfig config, BaseGround ground, PduBus& bus)
    : config_(config),
      bus_(bus),
      records_(std::move(ground)),
      // A digest the caller already holds is taken as given; otherwise through the digester,
      // which keeps the ground's hash state: later digests re-read only the features while the
      // ground stays as loaded.
      ground_digest_(config.ground_digest ? *config.ground_digest
                                          : digester_.Of(records_.terrain())),
      scheduler_(config.playback_window, config.playback_window_max, config.playback_retry_ms) {
  CheckConfig(config_);
  DT_LOG_INFO("replica {}: ground {} ({})", config_.address.ToString(), ground_digest_.ToHex(),
              config_.ground_source);
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
      AntiEntropyConfig{.self = config_.address,
                        .role = config_.role,
                        .period_ms = config_.anti_entropy_period_ms,
                        .retry_ms = config_.playback_retry_ms,
                        .silence_ms = config_.silence_ms,
                        .store = config_.store,
                        .drop_unreported_ms = config_.gap_give_up_ms},
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

// ---- periodic work ----

bool Replica::IsSilent(NodeAddress node) const {
  auto it = peers_.find(node);
  return it == peers_.end() || it->second.last_heard_ms < 0 ||
         now_ms_ - it->second.last_heard_ms > config_.silence_ms;
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

Status Replica::Flush() {
  Commit();
  return store_status_;
}

void Replica::Tick(int64_t now_ms) {
  // The tick's PDUs (requests, summaries, re-sends) leave packed, at its end.
  PduBus::Batch batch(bus_);
  now_ms_ = std::max(now_ms_, now_ms);
  scheduler_.OnTick(now_ms_);
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
    if (!exercise_ground_ &&
        ((server_answered_ && peers_answered && waited >= config_.silence_ms) ||
         (!config_.require_server && waited >= config_.silence_ms))) {
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

std::string Replica::Digest() const { return digester_.Of(records_.terrain()).ToHex(); }

bool Replica::caught_up() const {
  if (anti_entropy_->diverged()) return false;
  for (const auto& [author, log] : logs_) {
    if (log.has_gap()) return false;
  }
  return true;
}

std::map<NodeAddress, TerrainDigest> Replica::ground_mismatches() const {
  std::map<NodeAddress, TerrainDigest> out;
  for (const auto& [peer, digest] : peer_grounds_) {
    if (digest != ground_digest_) out.emplace(peer, digest);
  }
  return out;
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
