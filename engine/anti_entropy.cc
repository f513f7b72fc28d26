#include "engine/anti_entropy.h"

#include <algorithm>

#include <fmt/format.h>

#include "engine/change_hash.h"
#include "log/log.h"
#include "pdu/conversion.h"

namespace dt {
namespace {

Result<Change> ChangeOf(const dtpdu::construct_t& pdu) {
  auto f = FromConstruct(pdu);
  if (!f) return f.error();
  return ChangeFrom(f.value(), ChangeKind::kConstruct);
}
Result<Change> ChangeOf(const dtpdu::update_t& pdu) {
  auto f = FromUpdate(pdu);
  if (!f) return f.error();
  return ChangeFrom(f.value(), ChangeKind::kUpdate);
}
Result<Change> ChangeOf(const dtpdu::earth_move_t& pdu) {
  auto f = FromEarthMove(pdu);
  if (!f) return f.error();
  return ChangeFrom(f.value(), ChangeKind::kConstruct);
}
Result<Change> ChangeOf(const dtpdu::destruct_t& pdu) {
  auto d = FromDestruct(pdu);
  if (!d) return d.error();
  return ChangeFrom(d.value());
}

// The author of the change a PDU carries (a Construct names it created_by: the fingerprints of
// Construct and Update must differ).
NodeAddress AuthorOf(const dtpdu::construct_t& pdu) { return FromPdu(pdu.created_by); }
NodeAddress AuthorOf(const dtpdu::earth_move_t& pdu) { return FromPdu(pdu.moved_by); }
template <typename ChangePdu>
NodeAddress AuthorOf(const ChangePdu& pdu) {
  return FromPdu(pdu.changed_by);
}

// "3, 17, 18" for the first few slots of a set, "..." after them.
std::string SlotList(const std::set<int64_t>& slots) {
  std::string out;
  size_t n = 0;
  for (int64_t s : slots) {
    if (n++ == 8) return out + ", ...";
    out += (out.empty() ? "" : ", ") + std::to_string(s);
  }
  return out;
}

}  // namespace

AntiEntropy::AntiEntropy(AntiEntropyConfig config, Logs& logs, RecordStore& records, PduBus& bus,
                         PublishCopy publish, Replaced replaced, Admission admission,
                         HeldBeyond held_beyond)
    : config_(config),
      logs_(logs),
      records_(records),
      bus_(bus),
      publish_(std::move(publish)),
      replaced_(std::move(replaced)),
      admission_(std::move(admission)),
      held_beyond_(std::move(held_beyond)) {
  if (config_.period_ms <= 0) return;  // off: no summaries, no answers
  bus_.Subscribe<dtpdu::anti_entropy_t>([this](const dtpdu::anti_entropy_t& p) { OnPdu(p); });
  bus_.Subscribe<dtpdu::construct_t>([this](const dtpdu::construct_t& p) { OnCopy(p); });
  bus_.Subscribe<dtpdu::update_t>([this](const dtpdu::update_t& p) { OnCopy(p); });
  bus_.Subscribe<dtpdu::destruct_t>([this](const dtpdu::destruct_t& p) { OnCopy(p); });
  bus_.Subscribe<dtpdu::earth_move_t>([this](const dtpdu::earth_move_t& p) { OnCopy(p); });
}

// ---- queries ----

int64_t AntiEntropy::diverged_since_ms() const {
  int64_t since = -1;
  for (const auto& [key, d] : divergences_) {
    if (since < 0 || d.since_ms < since) since = d.since_ms;
  }
  return since;
}

std::vector<AntiEntropy::Divergence> AntiEntropy::divergences() const {
  std::vector<Divergence> out;
  for (const auto& [key, d] : divergences_) out.push_back(d);
  return out;
}

const ChangeLog* AntiEntropy::FindLog(NodeAddress author) const {
  auto it = logs_.find(author);
  return it == logs_.end() ? nullptr : &it->second;
}

PrefixHashes& AntiEntropy::Prefix(NodeAddress author) {
  PrefixHashes& p = prefixes_[author];
  if (const ChangeLog* log = FindLog(author)) p.Extend(*log);
  return p;
}

// ---- periodic work ----

void AntiEntropy::Tick(int64_t now_ms) {
  if (config_.period_ms <= 0) return;
  now_ms_ = std::max(now_ms_, now_ms);
  if (!pending_store_.empty()) FlushStore();
  ForgetSilentPeers();
  if (config_.role == NodeRole::kObserver) DropWhatOnlyThisHolds();
  RetryAsks();
  if (last_summary_ms_ < 0 || now_ms_ - last_summary_ms_ >= config_.period_ms) {
    last_summary_ms_ = now_ms_;
    SendSummaries();
  }
}

void AntiEntropy::Send(dtpdu::anti_entropy_t pdu) {
  pdu.num_entries = static_cast<int16_t>(pdu.entries.size());
  pdu.num_hashes = static_cast<int16_t>(pdu.hashes.size());
  pdu.role = static_cast<uint8_t>(config_.role);
  const auto bytes = static_cast<uint64_t>(pdu.getEncodedSize());
  if (auto s = bus_.Publish(pdu); !s) {
    DT_LOG_WARN("replica {}: sending an anti-entropy PDU (kind {}) failed: {}",
                config_.self.ToString(), pdu.kind, s.error().message);
    return;
  }
  stats_.bytes_sent += bytes;
}

void AntiEntropy::SendSummaries() {
  if (config_.role == NodeRole::kObserver) return;  // it compares others' summaries only
  dtpdu::anti_entropy_t pdu{};
  pdu.kind = static_cast<uint8_t>(AntiEntropyKind::kSummary);
  for (const auto& [author, log] : logs_) {
    if (log.max_held() < 1) continue;
    const PrefixHashes& p = Prefix(author);
    dtpdu::anti_entropy_entry_t e{};
    e.author = ToPdu(author);
    e.seq = p.length();
    e.prefix_hash = static_cast<int64_t>(p.At(p.length()));
    e.max_held = std::max<int64_t>(log.max_held(), e.seq);
    pdu.entries.push_back(e);
    if (pdu.entries.size() == static_cast<size_t>(kMaxSummaryAuthors)) {
      Send(pdu);
      ++stats_.summaries_sent;
      pdu.entries.clear();
    }
  }
  if (!pdu.entries.empty()) {
    Send(pdu);
    ++stats_.summaries_sent;
  }
}

int64_t AntiEntropy::ForgetMs() const {
  return std::max<int64_t>(config_.silence_ms, 3 * int64_t{config_.period_ms});
}

void AntiEntropy::ForgetSilentPeers() {
  std::vector<NodeAddress> gone;
  for (auto& [addr, view] : peers_) {
    if (now_ms_ - view.last_heard_ms > ForgetMs()) {
      gone.push_back(addr);
      continue;
    }
    // A restarted peer no longer names the authors it lost.
    std::erase_if(view.gap_free,
                  [&](const auto& e) { return now_ms_ - e.second.seen_ms > ForgetMs(); });
  }
  for (NodeAddress peer : gone) {
    peers_.erase(peer);
    for (auto it = sessions_.begin(); it != sessions_.end();) {
      it = it->first.first == peer ? sessions_.erase(it) : std::next(it);
    }
    for (auto it = divergences_.begin(); it != divergences_.end();) {
      if (it->first.first != peer) {
        ++it;
        continue;
      }
      DT_LOG_INFO(
          "replica {}: {} is silent; its difference in {}'s log ({}..{}) is no longer followed",
          config_.self.ToString(), peer.ToString(), it->second.author.ToString(),
          it->second.first_seq, it->second.last_seq);
      from_exchange_.erase(it->first);
      it = divergences_.erase(it);
    }
  }
}

void AntiEntropy::RetryAsks() {
  std::vector<Key> given_up;
  for (auto& [key, s] : sessions_) {
    bool give_up = false;
    for (auto* asks : {&s.hash_asks, &s.copy_asks}) {
      for (auto& [start, ask] : *asks) {
        if (now_ms_ - ask.sent_ms < config_.retry_ms) continue;
        if (ask.attempts >= kMaxAttempts) {
          give_up = true;
          break;
        }
        ++ask.attempts;
        ask.sent_ms = now_ms_;
        if (asks == &s.hash_asks) {
          SendHashRequest(key.first, key.second, start, ask.end);
        } else {
          SendCopyRequest(key.first, key.second, start, ask.end, s.exchange);
        }
      }
      if (give_up) break;
    }
    if (give_up) given_up.push_back(key);
  }
  for (const Key& key : given_up) {
    DT_LOG_INFO("replica {}: {} did not answer for {}'s log; the next summary starts again",
                config_.self.ToString(), key.first.ToString(), key.second.ToString());
    ++stats_.sessions_given_up;
    EndSession(key);
  }
}

// ---- receiving ----

void AntiEntropy::OnPdu(const dtpdu::anti_entropy_t& pdu) {
  stats_.bytes_received += static_cast<uint64_t>(pdu.getEncodedSize());
  const NodeAddress peer = FromPdu(pdu.sender);
  if (peer == config_.self) return;
  const auto role = static_cast<NodeRole>(pdu.role);
  // A stranger, or a member claiming a role the exercise file does not give it (it would win
  // the repair rule), is not heard.
  if (admission_.peer && !admission_.peer(peer, role)) return;
  const auto kind = static_cast<AntiEntropyKind>(pdu.kind);
  // An observer only asks: it holds no slot for the repair rule, and nobody fetches its copies.
  const bool observer = role == NodeRole::kObserver;
  if (observer && kind == AntiEntropyKind::kSummary) return;
  PeerView& view = peers_[peer];
  view.last_heard_ms = now_ms_;
  view.role = role;
  if (kind == AntiEntropyKind::kSummary) {
    OnSummary(peer, pdu);
    return;
  }
  if (FromPdu(pdu.target) != config_.self) return;
  const NodeAddress author = FromPdu(pdu.subject);
  switch (kind) {
    case AntiEntropyKind::kHashRequest:
      OnHashRequest(peer, author, pdu.start, pdu.end);
      break;
    case AntiEntropyKind::kHashAnswer:
      OnHashAnswer(peer, pdu);
      break;
    case AntiEntropyKind::kCopyRequest:
      OnCopyRequest(peer, author, pdu.start, pdu.end, pdu.exchange && !observer);
      break;
    case AntiEntropyKind::kCopies:
      OnCopies(peer, pdu);
      break;
    case AntiEntropyKind::kSummary:
      break;
  }
}

void AntiEntropy::OnSummary(NodeAddress peer, const dtpdu::anti_entropy_t& pdu) {
  ++stats_.summaries_received;
  PeerView& view = peers_[peer];
  for (const auto& e : pdu.entries) {
    const NodeAddress author = FromPdu(e.author);
    view.gap_free[author] = PeerView::Held{e.seq, now_ms_, e.max_held};
    const ChangeLog* log = FindLog(author);
    if (held_beyond_ && e.max_held > (log == nullptr ? 0 : log->max_known())) {
      held_beyond_(peer, author, e.max_held);
    }
    if (e.seq == 0) continue;  // nothing held without a gap: no prefix to compare
    // Compared where both hold the prefix; the peer compares the other way round when this
    // replica's gap-free point is the lower one.
    if (log == nullptr || log->contiguous() < e.seq) continue;
    const Key key{peer, author};
    if (Prefix(author).At(e.seq) == static_cast<uint64_t>(e.prefix_hash)) {
      Agrees(key);
    } else {
      Differs(key, e.seq);
    }
  }
}

void AntiEntropy::Agrees(const Key& key) {
  sessions_.erase(key);
  from_exchange_.erase(key);
  auto it = divergences_.find(key);
  if (it == divergences_.end()) return;
  DT_LOG_INFO(
      "replica {}: its log of {} agrees with {}'s again ({} ms after the difference was "
      "found)",
      config_.self.ToString(), key.second.ToString(), key.first.ToString(),
      now_ms_ - it->second.since_ms);
  divergences_.erase(it);
}

void AntiEntropy::Differs(const Key& key, int64_t upto) {
  from_exchange_.erase(key);  // found here: open until a summary agrees
  auto [it, fresh] =
      divergences_.try_emplace(key, Divergence{key.second, key.first, 1, upto, now_ms_, false});
  if (fresh) {
    ++stats_.differences_found;
    DT_LOG_WARN("replica {}: its log of {} differs from {}'s within changes 1..{}; locating",
                config_.self.ToString(), key.second.ToString(), key.first.ToString(), upto);
  }
  if (sessions_.count(key) != 0) return;  // already locating or repairing
  Session& s = sessions_[key];
  s.exchange = config_.role != NodeRole::kObserver;  // an observer's copy never travels
  s.to_ask.emplace_back(1, upto);
  Pump(key);
}

void AntiEntropy::OnHashRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end) {
  dtpdu::anti_entropy_t answer = Addressed(AntiEntropyKind::kHashAnswer, peer, author, start, end);
  const ChangeLog* log = FindLog(author);
  if (log != nullptr && log->contiguous() >= end) {
    const PrefixHashes& p = Prefix(author);
    const int64_t k = AntiEntropyBucketCount(start, end);
    for (int64_t i = 0; i < k; ++i) {
      auto [lo, hi] = HashBucket(start, end, i);
      answer.hashes.push_back(static_cast<int64_t>(p.Range(lo, hi)));
    }
  }
  // No hashes: this replica does not hold the whole range without a gap.
  Send(std::move(answer));
  ++stats_.hash_answers_sent;
}

void AntiEntropy::OnHashAnswer(NodeAddress peer, const dtpdu::anti_entropy_t& pdu) {
  const Key key{peer, FromPdu(pdu.subject)};
  auto sit = sessions_.find(key);
  if (sit == sessions_.end()) return;
  Session& s = sit->second;
  auto ask = s.hash_asks.find(pdu.start);
  if (ask == s.hash_asks.end() || ask->second.end != pdu.end) return;  // a stale duplicate
  s.hash_asks.erase(ask);
  const ChangeLog* log = FindLog(key.second);
  if (pdu.hashes.empty() || log == nullptr || log->contiguous() < pdu.end) {
    EndSession(key);  // the prefix is no longer held on both sides: the next summary decides
    return;
  }
  const PrefixHashes& p = Prefix(key.second);
  for (size_t i = 0; i < pdu.hashes.size(); ++i) {
    auto [lo, hi] = HashBucket(pdu.start, pdu.end, static_cast<int64_t>(i));
    if (p.Range(lo, hi) == static_cast<uint64_t>(pdu.hashes[i])) continue;
    if (lo == hi) {
      s.differing.insert(lo);
    } else {
      s.to_ask.emplace_back(lo, hi);
    }
  }
  Pump(key);
}

void AntiEntropy::OnCopyRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end,
                                bool exchange) {
  dtpdu::anti_entropy_t marker = Addressed(AntiEntropyKind::kCopies, peer, author, start, end);
  marker.hashes.assign(static_cast<size_t>(end - start + 1), 0);  // 0: not held
  if (const ChangeLog* log = FindLog(author)) {
    for (const Change* c : log->Range(start, end)) {
      publish_(*c, peer);
      ++stats_.copies_sent;
      marker.hashes[static_cast<size_t>(c->stamp.change_seq - start)] =
          static_cast<int64_t>(ChangeHash(*c));
    }
  }
  Send(std::move(marker));
  if (!exchange) return;
  // The peer located a difference here: fetch its copies in turn, so this side applies the rule
  // too (it may be the one to change).
  const Key key{peer, author};
  if (divergences_.count(key) == 0) {
    divergences_.emplace(key, Divergence{author, peer, start, end, now_ms_, true});
    from_exchange_.insert(key);
    ++stats_.differences_found;
    DT_LOG_WARN("replica {}: {} finds its log of {} different in changes {}..{}; comparing copies",
                config_.self.ToString(), peer.ToString(), author.ToString(), start, end);
  }
  auto [it, fresh] = sessions_.try_emplace(key);
  Session& s = it->second;
  if (fresh) s.located = true;  // nothing to locate: the peer did
  if (s.copy_asks.count(start) != 0) return;
  SendCopyRequest(peer, author, start, end, /*exchange=*/false);
  s.copy_asks[start] = Ask{end, now_ms_, 1};
}

template <typename ChangePdu>
void AntiEntropy::OnCopy(const ChangePdu& pdu) {
  // Cheap for the traffic that is not a copy this replica asked for (every live change).
  if (sessions_.empty() || !pdu.is_playback || FromPdu(pdu.playback_for) != config_.self) return;
  const Key key{FromPdu(pdu.sender), AuthorOf(pdu)};
  auto sit = sessions_.find(key);
  if (sit == sessions_.end() || sit->second.copy_asks.empty()) return;
  Session& s = sit->second;
  const int64_t seq = pdu.change_seq;
  auto ask = s.copy_asks.upper_bound(seq);
  if (ask == s.copy_asks.begin() || seq > std::prev(ask)->second.end) return;
  auto change = ChangeOf(pdu);
  if (!change) return;  // cannot happen for a validated PDU
  s.received.insert_or_assign(seq, std::move(change).value());
}

void AntiEntropy::OnCopies(NodeAddress peer, const dtpdu::anti_entropy_t& pdu) {
  const Key key{peer, FromPdu(pdu.subject)};
  const int64_t start = pdu.start;
  const int64_t end = pdu.end;
  auto sit = sessions_.find(key);
  if (sit == sessions_.end()) return;
  Session& s = sit->second;
  auto ask = s.copy_asks.find(start);
  if (ask == s.copy_asks.end() || ask->second.end != end) return;
  s.copy_asks.erase(ask);
  // Copies lost on the way are not decided: the next summary finds the slot again.
  // Only the copies this marker closes: one from an earlier answer (a retry's duplicate arriving
  // late) may be a copy the peer has replaced since.
  std::vector<Change> copies;
  for (auto it = s.received.lower_bound(start); it != s.received.end() && it->first <= end;) {
    const auto sent = static_cast<uint64_t>(pdu.hashes[static_cast<size_t>(it->first - start)]);
    if (ChangeHash(it->second) == sent) copies.push_back(std::move(it->second));
    it = s.received.erase(it);
  }
  Pump(key);  // may end the session: `s` is not used below
  for (const Change& c : copies) {
    if (!admission_.copy || admission_.copy(peer, c)) Decide(peer, c);
  }
}

// ---- locating ----

dtpdu::anti_entropy_t AntiEntropy::Addressed(AntiEntropyKind kind, NodeAddress target,
                                             NodeAddress author, int64_t start, int64_t end) const {
  dtpdu::anti_entropy_t pdu{};
  pdu.kind = static_cast<uint8_t>(kind);
  pdu.target = ToPdu(target);
  pdu.subject = ToPdu(author);
  pdu.start = start;
  pdu.end = end;
  return pdu;
}

void AntiEntropy::SendHashRequest(NodeAddress peer, NodeAddress author, int64_t start,
                                  int64_t end) {
  Send(Addressed(AntiEntropyKind::kHashRequest, peer, author, start, end));
  ++stats_.hash_requests_sent;
}

void AntiEntropy::SendCopyRequest(NodeAddress peer, NodeAddress author, int64_t start, int64_t end,
                                  bool exchange) {
  dtpdu::anti_entropy_t pdu = Addressed(AntiEntropyKind::kCopyRequest, peer, author, start, end);
  pdu.exchange = exchange;
  Send(std::move(pdu));
  ++stats_.copy_requests_sent;
}

void AntiEntropy::Pump(const Key& key) {
  auto sit = sessions_.find(key);
  if (sit == sessions_.end()) return;
  Session& s = sit->second;
  while (s.hash_asks.size() < kMaxOutstanding && !s.to_ask.empty()) {
    auto [lo, hi] = s.to_ask.front();
    s.to_ask.pop_front();
    SendHashRequest(key.first, key.second, lo, hi);
    s.hash_asks[lo] = Ask{hi, now_ms_, 1};
  }
  if (!s.located && s.hash_asks.empty() && s.to_ask.empty()) {
    s.located = true;
    if (!s.differing.empty()) {
      auto d = divergences_.find(key);
      if (d != divergences_.end()) {
        d->second.first_seq = *s.differing.begin();
        d->second.last_seq = *s.differing.rbegin();
        d->second.located = true;
      }
      DT_LOG_INFO("replica {}: located the difference with {} in {}'s log: change(s) {}",
                  config_.self.ToString(), key.first.ToString(), key.second.ToString(),
                  SlotList(s.differing));
      // Runs of consecutive slots, at most kMaxCopySpan each.
      for (auto it = s.differing.begin(); it != s.differing.end();) {
        const int64_t lo = *it;
        int64_t hi = lo;
        for (++it; it != s.differing.end() && *it == hi + 1 && hi + 1 - lo < kMaxCopySpan; ++it) {
          ++hi;
        }
        if (s.copy_asks.count(lo) != 0) continue;  // asked already, for the peer's exchange
        SendCopyRequest(key.first, key.second, lo, hi, s.exchange);
        s.copy_asks[lo] = Ask{hi, now_ms_, 1};
      }
    }
  }
  if (s.located && s.hash_asks.empty() && s.copy_asks.empty()) EndSession(key);
}

void AntiEntropy::EndSession(const Key& key) {
  sessions_.erase(key);
  // A difference a peer told us of is over with its exchange: the peer keeps following it.
  if (from_exchange_.erase(key) != 0) divergences_.erase(key);
}

}  // namespace dt
